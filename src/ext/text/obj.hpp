// OBJ: `v x y z [...]` (the first three numbers; w or colours are not read) and `f` lines of at
// least three v, v/vt, v/vt/vn or v//vn references: 1-based, or negative (-1 is the last vertex
// defined above the line, as the OBJ specification says); texture and normal indices are checked
// for syntax and for 0 only.  A face vertex may be defined below the face.  Polygons are fanned
// from their first vertex.  A '#' ends a face line; a backslash ending a line joins the next.
// Every other line (vt, vn, o, g, usemtl, s, l, comments ...) is skipped.
#pragma once
#include <algorithm>

#include "text/lexer.hpp"

namespace inertia::text {

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
// index + 1 named; `quads` the first of the two triangles of each quadrilateral.
inline Mesh obj_pass(const Lexer &t, int64_t limit, int64_t &largest, std::vector<int64_t> &quads) {
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
            if (count == 4) quads.push_back(int64_t(first_face));
        }
        i = t.end_of_line(i) + 1;
    }
    return m;
}

// Re-split each quadrilateral a b c d, fanned as (a b c), (a c d), along its shorter diagonal:
// (a b d), (b c d) when |b - d| <= |a - c| (MuJoCo's rule: ties take b-d).
inline void split_quads_shorter(Mesh &m, const std::vector<int64_t> &quads) {
    const double *v = m.vertices.data();
    auto dist2 = [&](int64_t p, int64_t q) {
        const double x = v[3 * p] - v[3 * q], y = v[3 * p + 1] - v[3 * q + 1], z = v[3 * p + 2] - v[3 * q + 2];
        return x * x + y * y + z * z;
    };
    for (int64_t q : quads) {
        int64_t *f = &m.faces[3 * q];
        const int64_t a = f[0], b = f[1], c = f[2], e = f[5];
        if (dist2(a, c) < dist2(b, e)) continue;
        const int64_t split[6] = {a, b, e, b, c, e};
        std::copy(split, split + 6, f);
    }
}

// Vertices and triangles of an OBJ (0-based), or its first error (with the line of an index
// beyond the last vertex, found by a second pass).
inline Mesh read_obj(const uint8_t *d, size_t n, bool shorter) {
    const Lexer t{d, n, true};
    std::vector<int64_t> quads;
    int64_t largest = 0, unused = 0;
    Mesh m = obj_pass(t, -1, largest, quads);
    const int64_t nv = int64_t(m.vertices.size() / 3);
    if (m.error.kind == OK && largest > nv) {
        std::vector<int64_t> ignored;
        m.error = obj_pass(t, nv, unused, ignored).error;
    }
    if (m.error.kind == OK && shorter) split_quads_shorter(m, quads);
    return m;
}

}  // namespace inertia::text
