// Volume and surface integrals of triangle meshes as per-face sums (formulas and error
// analysis: inertia/geometry/integrals.py).  The summation order depends on the face order
// alone: blocks of SUM_BLOCK faces, each summed in 4 lanes (face i in lane i mod 4) whose totals
// are added in a fixed order; block sums added into chunk totals of SUM_CHUNK faces, chunk totals
// added in order.  So a sum's error grows like (SUM_BLOCK + F / SUM_BLOCK) u, and every call on
// the same arrays gives the same bits, with or without AVX.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "common/isa.hpp"
#include "common/vec3.hpp"

namespace inertia {
INERTIA_ISA_BEGIN

// A per-face body inlined into its loop, so that the block's accumulators stay in registers.
#if defined(__GNUC__)
#define INERTIA_INLINE __attribute__((always_inline))
#else
#define INERTIA_INLINE
#endif

constexpr size_t SUM_BLOCK = 256;
constexpr size_t SUM_CHUNK = 64 * SUM_BLOCK;

// The sums of `quad(i, m, t)` over the faces [0, nf) in the order above: faces i .. i + m - 1
// (m <= 4, in lanes 0 .. m - 1, the other lanes zero) add their terms into the lanes of t[0..K);
// a block's lanes are added in a fixed order.  `quad` returns false to stop (then so does this,
// out partial).
template <size_t K, class Quad>
bool blocked_sum(size_t nf, double *out, Quad &&quad) {
    std::fill(out, out + K, 0.0);
    for (size_t c0 = 0; c0 < nf; c0 += SUM_CHUNK) {
        const size_t c1 = std::min(c0 + SUM_CHUNK, nf);
        double chunk[K] = {};
        for (size_t b0 = c0; b0 < c1; b0 += SUM_BLOCK) {
            const size_t b1 = std::min(b0 + SUM_BLOCK, c1);
            d4 t[K] = {};
            for (size_t i = b0; i < b1; i += 4)
                if (!quad(i, std::min<size_t>(4, b1 - i), t)) return false;
            for (size_t k = 0; k < K; ++k) chunk[k] += lanes_sum(t[k]);
        }
        for (size_t k = 0; k < K; ++k) out[k] += chunk[k];
    }
    return true;
}

// Ask for the rows of the m faces f[0..3m) ahead of their use: their gathers miss the cache on
// meshes whose faces jump around the vertex array.  (Integer address arithmetic: a bad index is
// only checked when its face is reached, and a prefetch never faults.)
constexpr size_t PREFETCH_FACES = 16;
constexpr size_t PREFETCH_MIN_ROWS = size_t(1) << 16;  // below (1.5 MB of rows) they stay in cache
inline void prefetch_rows(const double *v, const int64_t *f, size_t m) {
    for (size_t j = 0; j < 3 * m; ++j)
        __builtin_prefetch(reinterpret_cast<const void *>(reinterpret_cast<uintptr_t>(v) + 24 * uint64_t(f[j])));
}

inline d4 sqrt4(const d4 &x) {
    d4 r;
    for (int l = 0; l < 4; ++l) r[l] = std::sqrt(x[l]);
    return r;
}

// t[0..10) += w, w s (3), w Q (xx, yy, zz, xy, yz, zx) with s = a + b + c and
// Q = a a^T + b b^T + c c^T + s s^T.
template <class T>
inline void add_moments(T *t, const T &w, const Vec3<T> &a, const Vec3<T> &b, const Vec3<T> &c) {
    const Vec3<T> s = a + b + c;
    t[0] += w;
    t[1] += w * s.x;
    t[2] += w * s.y;
    t[3] += w * s.z;
    t[4] += w * (a.x * a.x + b.x * b.x + c.x * c.x + s.x * s.x);
    t[5] += w * (a.y * a.y + b.y * b.y + c.y * c.y + s.y * s.y);
    t[6] += w * (a.z * a.z + b.z * b.z + c.z * c.z + s.z * s.z);
    t[7] += w * (a.x * a.y + b.x * b.y + c.x * c.y + s.x * s.y);
    t[8] += w * (a.y * a.z + b.y * b.z + c.y * c.z + s.y * s.z);
    t[9] += w * (a.z * a.x + b.z * b.x + c.z * c.x + s.z * s.x);
}

// Center of the axis-aligned bounding box of the rows of v (nv >= 1).
inline V3 bbox_center(const double *v, size_t nv) {
    V3 lo = row(v, 0), hi = lo;
    for (size_t j = 1; j < nv; ++j) {
        const V3 x = row(v, j);
        lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
        hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
    }
    return {0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), 0.5 * (lo.z + hi.z)};
}

// Unscaled sums about p into out[10]: the solid's (w = det = a . ((b - a) x (c - a)), divide by
// 6, 24, 120) or the shell's (w = |(b - a) x (c - a)|, divide by 2, 6, 24); a, b, c the corners
// minus p.  The edge form of det keeps its error relative to |a| |n|, not |a| |b| |c|.  False at
// a face index outside [0, nv) (the caller names it: check_faces).
template <bool Shell>
bool mesh_sums(const double *v, size_t nv, const int64_t *faces, size_t nf, const V3 &p, double *out) {
    const int64_t n = static_cast<int64_t>(nv);
    const bool prefetch = nv >= PREFETCH_MIN_ROWS;
    return blocked_sum<10>(nf, out, [&](size_t i, size_t m, d4 *t) INERTIA_INLINE {
        const int64_t *f = faces + 3 * i;
        if (prefetch && i + PREFETCH_FACES + 4 <= nf) prefetch_rows(v, f + 3 * PREFETCH_FACES, 4);
        for (size_t j = 0; j < 3 * m; ++j)
            if (f[j] < 0 || f[j] >= n) return false;
        const V3x4 a = corners(v, f, m, 0, p), b = corners(v, f, m, 1, p), c = corners(v, f, m, 2, p);
        const V3x4 nrm = cross(b - a, c - a);
        add_moments(t, Shell ? sqrt4(dot(nrm, nrm)) : dot(a, nrm), a, b, c);
        return true;
    });
}

INERTIA_ISA_END
}  // namespace inertia
