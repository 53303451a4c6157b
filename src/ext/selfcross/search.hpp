// The face-pair search for the shells the star certificate cannot prove: the cell proof first
// (cellproof.hpp), then, over the faces it leaves, a uniform grid whose cells are hashed into
// buckets; each pair of faces whose boxes overlap is tested once with tris_cross, except pairs
// that share an edge (they cannot cross) and pairs around a vertex whose fan is certified flat.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/errors.hpp"
#include "selfcross/cellproof.hpp"
#include "selfcross/crossing.hpp"

namespace inertia::selfcross {

constexpr double SEARCH_CELLS_PER_FACE = 64;   // a face spanning more cells makes the grid twice as coarse
constexpr size_t HEIGHTFIELD_MIN_FACES = 256;  // the cell proof pays from about this size
constexpr size_t KEPT_WITHOUT_FANS = 16;       // fewer kept faces than 1 in this: no fan certificates
constexpr double FAN_ORIENT_RTOL = 1e-6;       // a fan's faces face along the sum of their normals beyond this
constexpr double FAN_SECTOR_RTOL = 1e-9;       // the first sector's bisector clear of the others' by this

// The fan of faces ts[:k] around v (face u turns v -> A[u] -> B[u]; the corners close into
// cycles) is flat: every face positively oriented seen along the sum of their normals, and the
// first sector's bisector in no other face's sector.  The projected sectors then wind around v
// once, so they are disjoint, and faces whose projections meet only at v meet only there.
template <class Index>
inline bool fan_certified(const double *V, const double *N, int64_t v, const Index *ts, const int64_t *A,
                          const int64_t *B, int64_t k) {
    double nx = 0.0, ny = 0.0, nz = 0.0;
    for (int64_t u = 0; u < k; ++u) {
        const double *n = N + 3 * ts[u];
        nx += n[0], ny += n[1], nz += n[2];
    }
    const double nn = std::sqrt(nx * nx + ny * ny + nz * nz);
    if (!(nn > 0.0)) return false;
    for (int64_t u = 0; u < k; ++u) {
        const double *n = N + 3 * ts[u];
        const double m = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(n[0] * nx + n[1] * ny + n[2] * nz > FAN_ORIENT_RTOL * m * nn)) return false;
    }
    nx /= nn, ny /= nn, nz /= nn;
    const double *p = V + 3 * v;
    double r[3] = {0.0, 0.0, 0.0};  // the first sector's bisector: its edges' unit projections, added
    for (int64_t c : {A[0], B[0]}) {
        double ex = V[3 * c] - p[0], ey = V[3 * c + 1] - p[1], ez = V[3 * c + 2] - p[2];
        const double h = ex * nx + ey * ny + ez * nz;
        ex -= h * nx, ey -= h * ny, ez -= h * nz;
        const double le = std::sqrt(ex * ex + ey * ey + ez * ez);
        if (!(le > 0.0)) return false;
        r[0] += ex / le, r[1] += ey / le, r[2] += ez / le;
    }
    const double lr = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (!(lr > 0.0)) return false;
    for (int64_t u = 1; u < k; ++u) {
        bool inside = true;
        for (int side = 0; side < 2 && inside; ++side) {
            const int64_t c = side == 0 ? A[u] : B[u];
            const double sgn = side == 0 ? 1.0 : -1.0;
            const double ex = V[3 * c] - p[0], ey = V[3 * c + 1] - p[1], ez = V[3 * c + 2] - p[2];
            // n . (e x r) for the first edge, n . (r x e) for the second
            const double o = sgn * (nx * (ey * r[2] - ez * r[1]) + ny * (ez * r[0] - ex * r[2]) + nz * (ex * r[1] - ey * r[0]));
            const double eps = FAN_SECTOR_RTOL * std::sqrt(ex * ex + ey * ey + ez * ez) * lr;
            if (o < -eps) inside = false;
            else if (o <= eps) return false;  // on the sector's edge, to rounding: no proof
        }
        if (inside) return false;
    }
    return true;
}

// Per vertex: 1 when no two faces around it meet but at the vertex and along common edges (so
// no pair of them can cross).  Only vertices with wanted[v] are tried.  Without adj, the faces
// are sorted by vertex and the corners after the vertex must close into cycles; with adj (the
// face across each edge of a closed shell) each fan is walked across its edges and must hold
// every face at the vertex (two cones touching at a vertex: not certified).
inline std::vector<uint8_t> certified_fans(const double *V, const int64_t *F, size_t nf, size_t nv, const double *N,
                                           const uint8_t *wanted, const int64_t *adj) {
    std::vector<uint8_t> cert(nv, 0);
    std::vector<int64_t> ts, A, B;
    auto turned = [&](int64_t t, int64_t v, int64_t n) {  // face t as v -> A[n] -> B[n]
        const int c = F[3 * t] == v ? 0 : F[3 * t + 1] == v ? 1 : 2;
        A[n] = F[3 * t + (c + 1) % 3];
        B[n] = F[3 * t + (c + 2) % 3];
        return c;
    };
    if (!adj) {
        const VertexSlots vs(F, nf, nv);
        int64_t kmax = 0;
        for (size_t i = 0; i < nv; ++i) kmax = std::max(kmax, vs.start[i + 1] - vs.start[i]);
        A.resize(kmax), B.resize(kmax);
        for (size_t v = 0; v < nv; ++v) {
            const int64_t s0 = vs.start[v], k = vs.start[v + 1] - s0;
            if (k < 3 || !wanted[v]) continue;
            for (int64_t u = 0; u < k; ++u) turned(vs.fac[s0 + u], int64_t(v), u);
            bool ok = true;  // the link closes: each corner as often an a as a b
            for (int64_t u = 0; u < k && ok; ++u) {
                const int64_t ca = std::count(A.begin(), A.begin() + k, A[u]);
                ok = ca == std::count(B.begin(), B.begin() + k, A[u]);
            }
            if (ok) cert[v] = fan_certified(V, N, int64_t(v), &vs.fac[s0], A.data(), B.data(), k);
        }
        return cert;
    }
    std::vector<int32_t> valence(nv, 0);
    std::vector<int64_t> seed(nv, -1);  // a corner 3 t + k at the vertex
    int64_t kmax = 0;
    for (size_t i = 0; i < 3 * nf; ++i) {
        const int64_t v = F[i];
        if (!wanted[v]) continue;
        kmax = std::max<int64_t>(kmax, ++valence[v]);
        if (seed[v] < 0) seed[v] = int64_t(i);
    }
    ts.resize(kmax), A.resize(kmax), B.resize(kmax);
    for (size_t v = 0; v < nv; ++v) {
        if (seed[v] < 0 || valence[v] < 3) continue;
        const int64_t t0 = seed[v] / 3;
        int64_t t = t0, n = 0;
        int c = int(seed[v] % 3);
        while (true) {
            if (n == valence[v]) {
                n = -1;  // more faces in the walk than at the vertex
                break;
            }
            ts[n] = t;
            A[n] = F[3 * t + (c + 1) % 3];
            B[n] = F[3 * t + (c + 2) % 3];
            ++n;
            t = adj[3 * t + (c + 2) % 3];  // across the edge b -> v: the face with v -> b
            if (t == t0) break;
            c = F[3 * t] == int64_t(v) ? 0 : F[3 * t + 1] == int64_t(v) ? 1 : 2;
        }
        if (n == valence[v]) cert[v] = fan_certified(V, N, int64_t(v), ts.data(), A.data(), B.data(), n);
    }
    return cert;
}

inline uint64_t bucket_of(int64_t x, int64_t y, int64_t z, uint64_t mask) {
    return ((uint64_t(x) * 73856093u) ^ (uint64_t(y) * 19349663u) ^ (uint64_t(z) * 83492791u)) & mask;
}

// Items t (begin <= t < end) with integer cell boxes lo[3 t..], hi[3 t..], filed by a counting
// sort in the buckets of the cells they cover (a bucket may hold several cells): bucket b holds
// item[start[b]:start[b + 1]], in increasing t; the buckets are the power of two at or above
// `registrations` (the cells the items cover, or about).
struct HashedCells {
    const int64_t *lo, *hi;
    uint64_t mask;
    std::vector<int64_t> start;
    Vec<int64_t> item;
    HashedCells(const int64_t *lo_, const int64_t *hi_, size_t begin, size_t end, int64_t registrations)
        : lo(lo_), hi(hi_), mask(capacity(registrations) - 1), start(mask + 2, 0) {
        for (size_t t = begin; t < end; ++t) each(t, [&](uint64_t b) { start[b + 1] += 1; });
        for (uint64_t b = 0; b <= mask; ++b) start[b + 1] += start[b];
        item.resize(size_t(start[mask + 1]));
        Vec<int64_t> fill(mask + 1);
        std::copy(start.begin(), start.end() - 1, fill.data());
        for (size_t t = begin; t < end; ++t) each(t, [&](uint64_t b) { item[fill[b]++] = int64_t(t); });
    }
    static uint64_t capacity(int64_t n) {
        uint64_t cap = 16;
        while (cap < uint64_t(n)) cap *= 2;
        return cap;
    }
    // fn(bucket) for each cell of item t's box
    template <class Fn>
    void each(size_t t, Fn &&fn) const {
        for (int64_t x = lo[3 * t]; x <= hi[3 * t]; ++x)
            for (int64_t y = lo[3 * t + 1]; y <= hi[3 * t + 1]; ++y)
                for (int64_t z = lo[3 * t + 2]; z <= hi[3 * t + 2]; ++z) fn(bucket_of(x, y, z, mask));
    }
};

// The cells lo, hi (3 per face) that the faces' boxes meet in a grid of `cell` from origin, and
// how many in all; -1 when a face meets more than SEARCH_CELLS_PER_FACE (or cells beyond int64).
inline int64_t cell_ranges(const double *V, const int64_t *Fs, size_t nf, const double *origin, double cell,
                           int64_t *lo, int64_t *hi) {
    int64_t n_reg = 0;
    for (size_t t = 0; t < nf; ++t) {
        double span = 1.0;  // in floats: a face 1e20 cells long must not overflow int64
        const double *p = V + 3 * Fs[3 * t], *q = V + 3 * Fs[3 * t + 1], *r = V + 3 * Fs[3 * t + 2];
        for (int a = 0; a < 3; ++a) {
            const double mn = std::floor((std::min({p[a], q[a], r[a]}) - origin[a]) / cell);
            const double mx = std::floor((std::max({p[a], q[a], r[a]}) - origin[a]) / cell);
            span *= mx - mn + 1.0;
            if (!(span <= SEARCH_CELLS_PER_FACE && mx <= 4.0e18)) return -1;
            lo[3 * t + a] = int64_t(mn);
            hi[3 * t + a] = int64_t(mx);
        }
        n_reg += int64_t(span);
    }
    return n_reg;
}

// A pair of crossing faces of Fs (rows of F, frames fr) into out: 1; 0 when none; -1 when a face
// spans more than SEARCH_CELLS_PER_FACE cells (the caller retries with a coarser grid).  The
// cells are hashed into buckets (a bucket may hold several cells); faces are filed per bucket by
// a counting sort, each entry with a float32 copy of its box (widened to hold it) and corners,
// so a bucket is read in sequence.  A pair is tested in the bucket of the lowest cell both
// boxes cover only (once whatever the collisions).
inline int grid_search(const double *V, const int64_t *Fs, size_t nf, const Frames &fr, const uint8_t *cert,
                       const double *origin, double cell, int64_t *out) {
    Vec<int64_t> lo(3 * nf), hi(3 * nf);
    const int64_t n_reg = cell_ranges(V, Fs, nf, origin, cell, lo.data(), hi.data());
    if (n_reg < 0) return -1;
    const HashedCells cells(lo.data(), hi.data(), 0, nf, n_reg);
    const uint64_t cap = cells.mask + 1, mask = cells.mask;
    const std::vector<int64_t> &counts = cells.start;
    struct Entry {
        float box[6];  // relative to origin, widened: float32 rounds to nearest
        int32_t cor[3], who;
    };
    Vec<Entry> ent(static_cast<size_t>(n_reg));
    const float grow = 2.4e-7f;
    for (int64_t r = 0; r < n_reg; ++r) {  // each entry with a copy of its face's box and corners
        const size_t t = size_t(cells.item[r]);
        Entry &e = ent[r];
        const double *p = V + 3 * Fs[3 * t], *q = V + 3 * Fs[3 * t + 1], *w = V + 3 * Fs[3 * t + 2];
        for (int a = 0; a < 3; ++a) {
            e.box[a] = float(std::min({p[a], q[a], w[a]}) - origin[a]);
            e.box[a] -= std::abs(e.box[a]) * grow + 1e-38f;
            e.box[a + 3] = float(std::max({p[a], q[a], w[a]}) - origin[a]);
            e.box[a + 3] += std::abs(e.box[a + 3]) * grow + 1e-38f;
            e.cor[a] = int32_t(Fs[3 * t + a]);
        }
        e.who = int32_t(t);
    }
    for (uint64_t b = 0; b < cap; ++b) {
        const int64_t c1 = counts[b + 1];
        for (int64_t p = counts[b]; p < c1; ++p) {
            const Entry &P = ent[p];
            for (int64_t q = p + 1; q < c1; ++q) {
                const Entry &Q = ent[q];
                if (Q.box[0] > P.box[3] || Q.box[3] < P.box[0] || Q.box[1] > P.box[4] || Q.box[4] < P.box[1] ||
                    Q.box[2] > P.box[5] || Q.box[5] < P.box[2])
                    continue;  // the boxes are apart
                int shared = 0;
                int32_t common = -1;
                for (int k = 0; k < 3; ++k)
                    if (Q.cor[k] == P.cor[0] || Q.cor[k] == P.cor[1] || Q.cor[k] == P.cor[2]) ++shared, common = Q.cor[k];
                if (shared >= 2) continue;                 // the same face, or neighbours across an edge
                if (shared == 1 && cert[common]) continue;  // faces around a certified vertex cannot cross
                const int64_t i = P.who, j = Q.who;
                if (bucket_of(std::max(lo[3 * i], lo[3 * j]), std::max(lo[3 * i + 1], lo[3 * j + 1]),
                              std::max(lo[3 * i + 2], lo[3 * j + 2]), mask) != b)
                    continue;  // tested in the bucket of the lowest cell both boxes cover
                if (tris_cross(fr.tri(V, Fs, i), fr.tri(V, Fs, j), CROSS_RTOL)) {
                    out[0] = std::min(i, j), out[1] = std::max(i, j);
                    return 1;
                }
            }
        }
    }
    return 0;
}

// A pair of faces of the closed shell (V, F) that cross into out (out[0] < out[1]): 1, or 0 when
// none.  adj: the face across each edge (face_twins), or null: then found here.  prove_cells
// false: no cell proof, every face searched.
inline int find_crossing(const double *V, const int64_t *F, size_t nf, size_t nv, const int64_t *adj,
                         bool prove_cells, int64_t *out) {
    if (nf < 2) return 0;
    if (nv > 4 * nf + 1024) {  // one shell of a large mesh: renumbered to its own vertices, work of its size
        std::vector<int64_t> used(F, F + 3 * nf), Fo(3 * nf);
        std::sort(used.begin(), used.end());
        used.erase(std::unique(used.begin(), used.end()), used.end());
        std::vector<double> Vo(3 * used.size());
        for (size_t i = 0; i < used.size(); ++i) std::copy(V + 3 * used[i], V + 3 * used[i] + 3, &Vo[3 * i]);
        for (size_t i = 0; i < 3 * nf; ++i) Fo[i] = std::lower_bound(used.begin(), used.end(), F[i]) - used.begin();
        return find_crossing(Vo.data(), Fo.data(), nf, used.size(), adj, prove_cells, out);
    }
    double origin[3], top[3];
    double cell = box_and_median_edge(V, F, nf, origin, top);
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(top[k] - origin[k]))
            input_error("self-crossing search: the vertices of the faces must be finite, with a finite extent");
    const double h = CELL_EDGES * cell;  // the cell proof's grid (it proves nothing if h is not finite)
    if (!(cell > 0.0 && cell < std::numeric_limits<double>::infinity())) cell = 1.0;
    std::vector<int64_t> rows;
    std::vector<int64_t> own_adj;
    if (prove_cells && nf >= HEIGHTFIELD_MIN_FACES) {
        if (!adj) {
            own_adj.resize(3 * nf);
            if (face_twins(F, nf, nv, own_adj.data())) adj = own_adj.data();
        }
        if (adj) {
            std::vector<uint8_t> keep(nf, 0);
            const int64_t n_keep = unproved_faces(V, F, nf, nv, adj, origin, top, h, keep.data());
            if (n_keep == 0) return 0;  // every cell proved
            if (size_t(n_keep) < nf)
                for (size_t t = 0; t < nf; ++t)
                    if (keep[t]) rows.push_back(int64_t(t));
        }
    }
    const bool all = rows.empty();
    const size_t ns = all ? nf : rows.size();
    std::vector<int64_t> Fsub;
    if (!all) {
        Fsub.resize(3 * ns);
        for (size_t r = 0; r < ns; ++r) std::copy(F + 3 * rows[r], F + 3 * rows[r] + 3, &Fsub[3 * r]);
    }
    const int64_t *Fs = all ? F : Fsub.data();
    const Frames fr(V, Fs, ns);
    std::vector<uint8_t> cert(nv, 0);
    // a few faces left (fewer than 1 in KEPT_WITHOUT_FANS): the fans' certificates (a pass over
    // every face) cost more than the pairs they spare
    if (ns * KEPT_WITHOUT_FANS >= nf) {
        std::vector<uint8_t> wanted(nv, all ? 1 : 0);
        for (size_t r = 0; r < (all ? 0 : ns); ++r)
            for (int k = 0; k < 3; ++k) wanted[Fs[3 * r + k]] = 1;
        // rows kept: the cell proof ran, adj matched, and each fan is walked across its edges
        cert = certified_fans(V, F, nf, nv, all ? fr.n.data() : Frames(V, F, nf).n.data(), wanted.data(),
                              all ? nullptr : adj);
    }
    while (true) {
        const int found = grid_search(V, Fs, ns, fr, cert.data(), origin, cell, out);
        if (found >= 0) {
            if (found == 1 && !all) {
                const int64_t i = rows[out[0]], j = rows[out[1]];
                out[0] = std::min(i, j), out[1] = std::max(i, j);
            }
            return found;
        }
        cell *= 2.0;
    }
}

// The first pair (i, j), lowest i then lowest j, of faces Fa[i] and Fb[j] (of the vertices V)
// that cross, among the faces whose boxes meet the box lo..hi, into out: 1; 0 when none, or
// when more than max_faces faces meet that box.  The faces of B are filed in a hashed grid of
// cells about two mean edges long; each face of A is tested against the faces of B whose boxes
// meet its own, in order.
inline int crossing_between(const double *V, const int64_t *Fa, size_t na, const int64_t *Fb, size_t nb,
                            const double *lo_, const double *hi_, size_t max_faces, int64_t *out) {
    std::vector<int64_t> rows, Fs;  // the faces meeting lo..hi, A's then B's (rows: B's as na + j)
    std::vector<double> box;        // their boxes, lo then hi
    double edges = 0.0, origin[3] = {INFINITY, INFINITY, INFINITY};
    for (size_t t = 0; t < na + nb; ++t) {
        const int64_t *f = t < na ? Fa + 3 * t : Fb + 3 * (t - na);
        double b[6];
        bool meets = true;
        for (int k = 0; k < 3; ++k) {
            b[k] = std::min({V[3 * f[0] + k], V[3 * f[1] + k], V[3 * f[2] + k]});
            b[3 + k] = std::max({V[3 * f[0] + k], V[3 * f[1] + k], V[3 * f[2] + k]});
            meets = meets && b[k] <= hi_[k] && b[3 + k] >= lo_[k];
        }
        if (!meets) continue;
        rows.push_back(int64_t(t));
        Fs.insert(Fs.end(), f, f + 3);
        box.insert(box.end(), b, b + 6);
        for (int k = 0; k < 3; ++k) {
            const double *p = V + 3 * f[k], *q = V + 3 * f[(k + 1) % 3];
            edges += std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]));
            origin[k] = std::min(origin[k], b[k]);
        }
    }
    const size_t n = rows.size(), ma = size_t(std::lower_bound(rows.begin(), rows.end(), int64_t(na)) - rows.begin());
    if (ma == 0 || ma == n || n > max_faces) return 0;
    double cell = 2.0 * edges / double(3 * n);
    if (!(cell > 0.0 && std::isfinite(cell))) return 0;  // every triangle a point: none crosses
    Vec<int64_t> lo(3 * n), hi(3 * n);
    int64_t n_reg;
    while ((n_reg = cell_ranges(V, Fs.data(), n, origin, cell, lo.data(), hi.data())) < 0)
        if (!std::isfinite(cell *= 2.0)) return 0;  // (not reached with finite boxes)
    const HashedCells cells(lo.data(), hi.data(), ma, n, n_reg);  // B's faces
    std::vector<int64_t> seen(n, -1), cand;
    auto tri = [&](size_t t) { return make_tri(V + 3 * Fs[3 * t], V + 3 * Fs[3 * t + 1], V + 3 * Fs[3 * t + 2]); };
    for (size_t i = 0; i < ma; ++i) {
        const double *bi = &box[6 * i];
        cand.clear();
        cells.each(i, [&](uint64_t b) {
            for (int64_t e = cells.start[b]; e < cells.start[b + 1]; ++e) {
                const int64_t j = cells.item[e];
                const double *bj = &box[6 * j];
                if (seen[j] == int64_t(i)) continue;
                seen[j] = int64_t(i);
                if (bj[0] <= bi[3] && bj[3] >= bi[0] && bj[1] <= bi[4] && bj[4] >= bi[1] && bj[2] <= bi[5] && bj[5] >= bi[2])
                    cand.push_back(j);
            }
        });
        std::sort(cand.begin(), cand.end());
        const Tri ti = tri(i);
        for (int64_t j : cand)
            if (tris_cross(ti, tri(size_t(j)), CROSS_RTOL)) {
                out[0] = rows[i], out[1] = rows[j] - int64_t(na);
                return 1;
            }
    }
    return 0;
}

}  // namespace inertia::selfcross
