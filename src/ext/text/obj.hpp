// OBJ: `v x y z [...]` (the first three numbers; w or colours are not read) and `f` lines of at
// least three v, v/vt, v/vt/vn or v//vn references: 1-based, or negative (-1 is the last vertex
// defined above the line, as the OBJ specification says); texture and normal indices are checked
// for syntax and for 0 only.  A face vertex may be defined below the face.  Polygons are fanned
// from their first vertex, or triangulated as MuJoCo's reader does (Polygons below).  A '#' ends
// a face line; a backslash ending a line joins the next.  Every other line (vt, vn, o, g, usemtl,
// s, l, comments ...) is skipped.
#pragma once
#include <algorithm>

#include "text/lexer.hpp"

namespace inertia::text {

// How polygons become triangles: fanned from the first vertex (trimesh); the same with quads split
// along their shorter diagonal; or as MuJoCo 4's reader (the tinyobjloader it vendors, in float):
// quads along the shorter diagonal, 5 to 100 vertices by its ear clipping, larger faces dropped,
// and the faces of the first `o`/`g` group with triangles only.
enum Polygons : int { FAN, SHORTER, MUJOCO };

// The signed integer at i (magnitudes capped at 2^62, beyond any vertex count): its end, i when none.
inline size_t obj_index(const Lexer &t, size_t i, int64_t &value) {
    constexpr int64_t cap = int64_t(1) << 62;
    const bool neg = i < t.n && t.d[i] == '-';
    size_t j = i + (i < t.n && (t.d[i] == '-' || t.d[i] == '+'));
    const size_t first = j;
    value = 0;
    for (; j < t.n && digit(t.d[j]); ++j) value = value < cap / 10 ? value * 10 + (t.d[j] - '0') : cap;
    if (neg) value = -value;
    return j == first ? i : j;
}

// One pass over the text; `limit` >= 0 refuses positive indices above it (the second pass
// that finds the line of an index beyond the last vertex); `largest` the largest vertex
// index + 1 named; `polys` (first fan triangle, vertices) of each face of 4 or more vertices;
// `groups` the triangles read before each `o` or `g` line (tinyobjloader's: one with a space or tab after).
inline Mesh obj_pass(const Lexer &t, int64_t limit, int64_t &largest, std::vector<int64_t> &polys,
                     std::vector<int64_t> &groups) {
    const uint8_t *d = t.d;
    const size_t n = t.n;
    Mesh m;
    auto fail = [&](TextError e) { return m.error = e, std::move(m); };
    auto keyword = [&](size_t i, char c) { return i < n && d[i] == c && t.word_ends(i + 1); };
    largest = 0;
    size_t i = 0;
    while (i < n) {
        const size_t line = i;
        i = t.skip_blanks(i);
        if (keyword(i, 'v')) {
            double c[3];
            ++i;
            if (!t.coordinates(i, line, c, m.error)) return m;
            m.vertices.insert(m.vertices.end(), c, c + 3);
        } else if (i + 1 < n && (d[i] == 'o' || d[i] == 'g') && (d[i + 1] == ' ' || d[i + 1] == '\t')) {
            groups.push_back(int64_t(m.faces.size() / 3));
        } else if (keyword(i, 'f')) {
            const int64_t nv = int64_t(m.vertices.size() / 3);
            const size_t first_face = m.faces.size() / 3;
            int64_t count = 0, first = 0, second = 0;
            for (++i;;) {
                i = t.skip_blanks(i);
                if (t.line_ends(i) || d[i] == '#') break;
                int64_t v, other;
                size_t j = obj_index(t, i, v);
                if (j == i) return fail(t.error(BAD_REF, line, i));
                bool zero = v == 0;
                for (int k = 0; k < 2 && j < n && d[j] == '/'; ++k) {  // /vt, /vt/vn, //vn
                    const size_t e = obj_index(t, ++j, other);
                    zero = zero || (e != j && other == 0);
                    j = e;
                }
                if (!t.word_ends(j, true)) return fail(t.error(BAD_REF, line, i));
                if (zero) return fail(t.error(ZERO_INDEX, line, i));
                if (v < 0) {
                    if (nv + v < 0) return fail(t.error(INDEX_RANGE, line, i, nv));
                    v += nv;
                } else {
                    if (limit >= 0 && v > limit) return fail(t.error(INDEX_RANGE, line, i, limit));
                    largest = std::max(largest, v--);
                }
                if (count == 0) first = v;
                if (count >= 2) m.faces.insert(m.faces.end(), {first, second, v});
                second = v;
                ++count;
                i = j;
            }
            if (count < 3) return fail(t.error(FEW_REFS, line, 0, count));
            if (count >= 4) polys.insert(polys.end(), {int64_t(first_face), count});
        }
        i = t.end_of_line(i) + 1;
    }
    return m;
}

// The two triangles of quadrilateral q as tinyobjloader splits it: (0 1 2), (0 2 3) when the
// diagonal 0-2 is shorter than 1-3 (in float), else (0 1 3), (1 2 3).
inline void split_quad(const std::vector<float> &v, const int64_t *q, std::vector<int64_t> &out) {
    auto dist2 = [&](int64_t p, int64_t r) {
        const float x = v[3 * r] - v[3 * p], y = v[3 * r + 1] - v[3 * p + 1], z = v[3 * r + 2] - v[3 * p + 2];
        return x * x + y * y + z * z;
    };
    if (dist2(q[0], q[2]) < dist2(q[1], q[3])) out.insert(out.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    else out.insert(out.end(), {q[0], q[1], q[3], q[1], q[2], q[3]});
}

// tinyobjloader's ear clipping of the polygon `loop` (its built-in triangulation, as MuJoCo 4 has
// it): projected on the two axes off the normal of the first corner that is no straight line; a
// corner is cut when its turn has the sign of the triangle (origin, its first two vertices) and no
// other vertex lies in it; clipping goes on from the same place; it stops after a full turn
// without a cut, and what is left then is dropped.
inline void clip_ears(const std::vector<float> &v, std::vector<int64_t> loop, std::vector<int64_t> &out) {
    const size_t n = loop.size();
    size_t ax0 = 1, ax1 = 2;
    for (size_t k = 0; k < n; ++k) {  // the plane of projection
        const float *a = &v[3 * loop[k]], *b = &v[3 * loop[(k + 1) % n]], *c = &v[3 * loop[(k + 2) % n]];
        const float e0x = b[0] - a[0], e0y = b[1] - a[1], e0z = b[2] - a[2];
        const float e1x = c[0] - b[0], e1y = c[1] - b[1], e1z = c[2] - b[2];
        const float cx = std::fabs(e0y * e1z - e0z * e1y), cy = std::fabs(e0z * e1x - e0x * e1z),
                    cz = std::fabs(e0x * e1y - e0y * e1x), eps = std::numeric_limits<float>::epsilon();
        if (cx > eps || cy > eps || cz > eps) {
            if (!(cx > cy && cx > cz)) {
                ax0 = 0;
                if (cz > cx && cz > cy) ax1 = 1;
            }
            break;
        }
    }
    auto x = [&](int64_t i) { return v[3 * i + ax0]; };
    auto y = [&](int64_t i) { return v[3 * i + ax1]; };
    size_t guess = 0, left = n, before = n;
    while (loop.size() > 3 && left > 0) {
        const size_t m = loop.size();
        if (guess >= m) guess -= m;
        if (before != m) before = left = m;
        else --left;
        const int64_t ind[3] = {loop[guess % m], loop[(guess + 1) % m], loop[(guess + 2) % m]};
        const float vx[3] = {x(ind[0]), x(ind[1]), x(ind[2])}, vy[3] = {y(ind[0]), y(ind[1]), y(ind[2])};
        const float cross = (vx[1] - vx[0]) * (vy[2] - vy[1]) - (vy[1] - vy[0]) * (vx[2] - vx[1]);
        const float area = (vx[0] * vy[1] - vy[0] * vx[1]) * 0.5f;
        bool cut = !(cross * area < 0.0f);
        for (size_t o = 3; cut && o < m; ++o) {  // another vertex inside: the crossing-number test (pnpoly)
            const float tx = x(loop[(guess + o) % m]), ty = y(loop[(guess + o) % m]);
            bool inside = false;
            for (size_t i = 0, j = 2; i < 3; j = i++)
                if ((vy[i] > ty) != (vy[j] > ty) && tx < (vx[j] - vx[i]) * (ty - vy[i]) / (vy[j] - vy[i]) + vx[i])
                    inside = !inside;
            cut = !inside;
        }
        if (!cut) {
            ++guess;
            continue;
        }
        out.insert(out.end(), ind, ind + 3);
        loop.erase(loop.begin() + std::ptrdiff_t((guess + 1) % m));
    }
    if (loop.size() == 3) out.insert(out.end(), loop.begin(), loop.end());
}

// The fanned polygons `polys` of m re-triangulated by `how` (SHORTER or MUJOCO; see Polygons).
inline void triangulate(Mesh &m, const std::vector<int64_t> &polys, const std::vector<int64_t> &groups,
                        Polygons how) {
    if (polys.empty() && (how != MUJOCO || groups.empty())) return;
    std::vector<float> v(m.vertices.size());  // as MuJoCo holds them (beyond float's range: infinite)
    std::transform(m.vertices.begin(), m.vertices.end(), v.begin(), [](double x) {
        constexpr float big = std::numeric_limits<float>::max(), inf = std::numeric_limits<float>::infinity();
        return x > big ? inf : x < -big ? -inf : float(x);
    });
    std::vector<int64_t> out, loop, group_of;  // group_of: the first triangle of each group in out
    out.reserve(m.faces.size());
    const int64_t *f = m.faces.data();
    const int64_t nf = int64_t(m.faces.size() / 3);
    size_t p = 0, g = 0;
    for (int64_t i = 0; i < nf;) {
        for (; g < groups.size() && groups[g] <= i; ++g) group_of.push_back(int64_t(out.size() / 3));
        if (p == polys.size() || polys[p] != i) {  // a triangle of the file
            out.insert(out.end(), f + 3 * i, f + 3 * i + 3);
            ++i;
            continue;
        }
        const int64_t count = polys[p + 1];
        p += 2;
        loop.assign({f[3 * i], f[3 * i + 1]});  // the polygon from its fan (v0 v1 v2), (v0 v2 v3) ...
        for (int64_t k = 0; k < count - 2; ++k) loop.push_back(f[3 * (i + k) + 2]);
        if (how == SHORTER && count > 4) out.insert(out.end(), f + 3 * i, f + 3 * (i + count - 2));
        else if (count == 4) split_quad(v, loop.data(), out);
        else if (count <= 100) clip_ears(v, loop, out);
        i += count - 2;
    }
    if (how == MUJOCO) {  // the first group (before the first o/g, then between them) with triangles
        group_of.push_back(int64_t(out.size() / 3));
        for (; g < groups.size(); ++g) group_of.push_back(int64_t(out.size() / 3));
        int64_t start = 0;
        for (int64_t end : group_of) {
            if (end > start) {
                out.erase(out.begin() + 3 * end, out.end());
                out.erase(out.begin(), out.begin() + 3 * start);
                break;
            }
            start = end;
        }
    }
    m.faces = std::move(out);
}

// Vertices and triangles of an OBJ (0-based), or its first error (with the line of an index
// beyond the last vertex, found by a second pass).
inline Mesh read_obj(const uint8_t *d, size_t n, Polygons how) {
    const Lexer t{d, n, true};
    std::vector<int64_t> polys, groups;
    int64_t largest = 0, unused = 0;
    Mesh m = obj_pass(t, -1, largest, polys, groups);
    const int64_t nv = int64_t(m.vertices.size() / 3);
    if (m.error.kind == OK && largest > nv) {
        std::vector<int64_t> ignored, ignored_groups;
        m.error = obj_pass(t, nv, unused, ignored, ignored_groups).error;
    }
    if (m.error.kind == OK && how != FAN) triangulate(m, polys, groups, how);
    return m;
}

}  // namespace inertia::text
