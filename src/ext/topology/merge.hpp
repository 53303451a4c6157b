// Near merging: vertices within a tolerance of the mesh size joined transitively, each group
// taking the coordinates of its lowest index; and the weld and merge of a binary STL's corners.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "topology/hash.hpp"
#include "topology/weld.hpp"

namespace inertia::topology {

// Merging never joins vertices farther apart than this fraction of the short face edges.
constexpr double MERGE_EDGE_FRACTION = 0.25;
// The grid's cells are this many tolerances wide: a point's box of +- tol leaves its cell
// with odds of about 6 / this.
constexpr double NEAR_CELL_TOLS = 256.0;
// float32 numbers of magnitude >= M are >= 2^-24 M apart: beyond this many tolerances two
// distinct float32 coordinates are more than 2 tolerances apart.
constexpr double F32_APART_TOLS = 67108864.0;  // 2^26

inline bool within(const double *v, int64_t i, int64_t j, double tol2) {
    const double d0 = v[3 * i] - v[3 * j], d1 = v[3 * i + 1] - v[3 * j + 1], d2 = v[3 * i + 2] - v[3 * j + 2];
    return d0 * d0 + d1 * d1 + d2 * d2 <= tol2;
}

// rep[i]: the lowest index of i's group, vertices joined when at distance <= tol; empty when
// the grid cannot number the cells (|x| / tol too large, or non-finite values).
// Grid hashing, cells NEAR_CELL_TOLS tol wide: each point is compared with the points filed
// before it in its own cell; a point whose box [x - tol, x + tol] leaves its cell is then also
// compared with the points of the other cells the box touches.  Two points within tol in
// different cells both have such boxes, so every pair is seen.
inline Vec<int64_t> near_merge_map(const double *v, size_t n, double tol) {
    const double inv = 1.0 / (NEAR_CELL_TOLS * tol), limit = 1152921504606846976.0;  // 2^60
    Vec<int64_t> cells(3 * n);
    for (size_t i = 0; i < 3 * n; ++i) {
        const double q = std::floor(v[i] * inv);
        if (!(std::fabs(q) < limit)) return {};
        cells[i] = int64_t(q);
    }
    const uint64_t cap = capacity(n), mask = cap - 1;
    Vec<int64_t> head(cap, -1), next(n, -1), parent(n);
    for (size_t i = 0; i < n; ++i) parent[i] = int64_t(i);
    const double tol2 = tol * tol, reach = tol * (1.0 + 1e-9);  // a cell touched only through rounding too
    auto slot_of = [&](const int64_t *c) {   // the slot of cell c, or of the empty slot where it would go
        uint64_t s = mix3(uint64_t(c[0]), uint64_t(c[1]), uint64_t(c[2])) & mask;
        for (; head[s] >= 0; s = (s + 1) & mask) {
            const int64_t *d = &cells[3 * size_t(head[s])];
            if (d[0] == c[0] && d[1] == c[1] && d[2] == c[2]) break;
        }
        return s;
    };
    auto join_cell = [&](int64_t i, int64_t j) {   // i with every point of the cell whose head is j
        for (; j >= 0; j = next[j])
            if (within(v, i, j, tol2)) union_low(parent.data(), i, j);
    };
    Vec<int64_t> leaving;
    for (size_t i = 0; i < n; ++i) {
        const uint64_t s = slot_of(&cells[3 * i]);
        join_cell(int64_t(i), head[s]);
        next[i] = head[s];
        head[s] = int64_t(i);
        for (int k = 0; k < 3; ++k)
            if (std::floor((v[3 * i + k] - reach) * inv) != double(cells[3 * i + k]) ||
                std::floor((v[3 * i + k] + reach) * inv) != double(cells[3 * i + k])) {
                leaving.push_back(int64_t(i));
                break;
            }
    }
    for (const int64_t i : leaving) {
        int64_t lo[3], hi[3], c[3];
        for (int k = 0; k < 3; ++k) {
            lo[k] = int64_t(std::floor((v[3 * i + k] - reach) * inv));
            hi[k] = int64_t(std::floor((v[3 * i + k] + reach) * inv));
        }
        const int64_t *own = &cells[3 * size_t(i)];
        for (c[0] = lo[0]; c[0] <= hi[0]; ++c[0])
            for (c[1] = lo[1]; c[1] <= hi[1]; ++c[1])
                for (c[2] = lo[2]; c[2] <= hi[2]; ++c[2])
                    if (!(c[0] == own[0] && c[1] == own[1] && c[2] == own[2])) join_cell(i, head[slot_of(c)]);
    }
    Vec<int64_t> rep(n);
    for (size_t i = 0; i < n; ++i) rep[i] = find_root(parent.data(), int64_t(i));
    return rep;
}

// True when no two rows of v (finite float32 values held as float64) are within tol of each
// other in every coordinate; false when not shown.  With T = F32_APART_TOLS tol, a near pair
// agrees on its coordinates of magnitude >= T (distinct float32 numbers that large are more
// than 2 tol apart), so rows whose reduced keys (those coordinates kept, the others 0) all
// differ hold no near pair.  Rows sharing a key are compared, up to n comparisons in all.
inline bool float32_apart(const double *v, size_t n, double tol, double maxabs) {
    const double big = F32_APART_TOLS * tol, inf = std::numeric_limits<double>::infinity();
    if (!(big >= 0x1p-100 && big < inf && maxabs < inf) || n >= (size_t(1) << 31))
        return false;   // float32 subnormals are 2^-149 apart; the table holds int32 rows
    const double scale = maxabs > 0.0 ? 0x1p30 / maxabs : 0.0;           // |key| x scale <= 2^30: an integer
    auto reduced = [big](double x) { return std::fabs(x) < big ? 0.0 : x; };
    const uint64_t cap = capacity(n), mask = cap - 1;
    Vec<int32_t> table(cap, -1);
    uint64_t compares = 0;
    for (size_t i = 0; i < n; ++i) {
        const double *p = v + 3 * i, a = reduced(p[0]), b = reduced(p[1]), c = reduced(p[2]);
        uint64_t s = mix3(uint64_t(int64_t(a * scale)), uint64_t(int64_t(b * scale)), uint64_t(int64_t(c * scale))) & mask;
        for (; table[s] >= 0; s = (s + 1) & mask) {
            const double *q = v + 3 * size_t(table[s]);
            if (reduced(q[0]) == a && reduced(q[1]) == b && reduced(q[2]) == c) {
                // the same key: apart if a coordinate differs by more than tol (the rounded
                // difference exceeds tol only if the exact one does: tol is a float)
                if (++compares > n || !(std::fabs(q[0] - p[0]) > tol || std::fabs(q[1] - p[1]) > tol ||
                                        std::fabs(q[2] - p[2]) > tol))
                    return false;
            }
        }
        table[s] = int32_t(i);
    }
    return true;
}

inline double edge_length2(const double *v, int64_t a, int64_t b) {
    const double d0 = v[3 * a] - v[3 * b], d1 = v[3 * a + 1] - v[3 * b + 1], d2 = v[3 * a + 2] - v[3 * b + 2];
    return d0 * d0 + d1 * d1 + d2 * d2;
}

// tol, at most MERGE_EDGE_FRACTION of the short edges of the faces (their 1st percentile):
// merging joins copies of a vertex, never the mesh's own features, wherever the mesh lies.
inline double capped_by_edges(const double *v, const int64_t *f, size_t nf, double tol) {
    double shortest = std::numeric_limits<double>::infinity();
    for (size_t h = 0; h < 3 * nf; ++h) {
        const double d = edge_length2(v, f[h], f[h - h % 3 + (h + 1) % 3]);
        if (d > 0.0 && d < shortest) shortest = d;
    }
    if (!(tol > MERGE_EDGE_FRACTION * std::sqrt(shortest))) return tol;   // the common case: far below every edge
    Vec<double> lengths;
    lengths.reserve(3 * nf);
    for (size_t h = 0; h < 3 * nf; ++h) {
        const double d = std::sqrt(edge_length2(v, f[h], f[h - h % 3 + (h + 1) % 3]));
        if (d > 0.0) lengths.push_back(d);
    }
    auto nth = lengths.begin() + (lengths.size() - 1) / 100;
    std::nth_element(lengths.begin(), nth, lengths.end());
    return std::min(tol, MERGE_EDGE_FRACTION * *nth);
}

// Merge the welded mesh m in place within rtol of its size (or 64 ulps of its largest
// coordinate, when larger), capped by its short edges.  `f32`: every coordinate is a float32
// value, first tried with float32_apart.  Returns 0, or the tolerance still to merge within
// when the grid cannot number the cells (m is then left welded).
inline double merge_near(Mesh &m, double rtol, bool f32) {
    const size_t n = m.n_vertices();
    if (n < 2 || !(rtol > 0.0)) return 0.0;
    const double inf = std::numeric_limits<double>::infinity();
    double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            const double x = m.v[3 * i + k];
            if (!std::isfinite(x)) return 0.0;   // non-finite coordinates: reported by the checks, not merged
            lo[k] = std::min(lo[k], x);
            hi[k] = std::max(hi[k], x);
        }
    double big = 0.0, scale = 0.0, e[3];
    for (int k = 0; k < 3; ++k) {
        big = std::max({big, -lo[k], hi[k]});
        e[k] = hi[k] - lo[k];
        scale = std::max(scale, e[k]);
    }
    if (!std::isfinite(scale)) return 0.0;   // coordinates near the float64 limit: nothing sensible to merge
    double diag = 0.0;
    if (scale > 0.0) {   // scaled: squares of extents near 1e200 do not overflow
        const double a = e[0] / scale, b = e[1] / scale, c = e[2] / scale;
        diag = scale * std::sqrt(a * a + b * b + c * c);
    }
    double tol = std::max(rtol * diag, 64.0 * std::numeric_limits<double>::epsilon() * big);
    if (!(tol > 0.0) || !std::isfinite(tol)) return 0.0;
    if (f32 && float32_apart(m.v.data(), n, tol, big)) return 0.0;   // capping by the edges only lowers tol
    tol = capped_by_edges(m.v.data(), m.f.data(), m.n_faces(), tol);
    const Vec<int64_t> rep = near_merge_map(m.v.data(), n, tol);
    if (rep.empty()) return tol;
    size_t i = 0;
    while (i < n && rep[i] == int64_t(i)) ++i;
    if (i == n) return 0.0;
    for (auto &x : m.f) x = rep[x];
    m = compact_groups<int64_t>(m.v.data(), m.f.data(), m.n_faces(), nullptr, n, nullptr);
    return 0.0;
}

// Little-endian 32-bit word at p (any alignment).
inline uint32_t le32(const uint8_t *p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// A binary STL's n records (50 bytes from `records`: normal, three float32 corners, attribute)
// welded by the corners' bits (-0.0 folded onto 0.0; a corner with a NaN or infinity alone) and
// merged: the arrays merge_near gives for the float64 soup of the corners, without the soup.
// Each vertex takes the float32 value of its first corner, exactly.
// `pending`: as merge_near returns.  I: the type of the group numbers (int32 while they fit: half the table).
template <class I>
Mesh stl_weld_and_merge(const uint8_t *records, size_t n, double rtol, double &pending) {
    const size_t corners = 3 * n;
    auto corner = [records](size_t i) { return records + 50 * (i / 3) + 12 + 12 * (i % 3); };
    const Groups<I> g = weld_groups<I, uint32_t>(corners, [&](size_t i, uint32_t *k) {
        const uint8_t *p = corner(i);
        for (int c = 0; c < 3; ++c) {
            const uint32_t w = le32(p + 4 * c);
            k[c] = w == 0x80000000u ? 0u : w;
        }
    });
    Mesh m;
    m.v.resize(3 * size_t(g.count));
    for (I t = 0; t < g.count; ++t) {
        const uint8_t *p = corner(size_t(g.first[t]));
        for (int c = 0; c < 3; ++c) {
            const uint32_t w = le32(p + 4 * c);
            float x;
            std::memcpy(&x, &w, 4);
            m.v[3 * size_t(t) + c] = double(x);
        }
    }
    m.f.assign(g.group.begin(), g.group.end());
    pending = merge_near(m, rtol, true);
    return m;
}

}  // namespace inertia::topology
