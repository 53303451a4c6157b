// 3-vectors for the per-face arithmetic, of doubles (V3) or of 4 faces at once (V3x4: one lane
// per face, GCC/Clang vector extensions; a build without AVX runs each as two SSE2 halves), and
// the same operations on rows of 3 doubles in place.  Every operation is the plain IEEE
// expression written left to right, lane by lane (no fused multiply-add: -ffp-contract=off), so
// a lane gives the bits its scalar twin would.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "common/isa.hpp"

#pragma GCC diagnostic ignored "-Wpsabi"  // 32-byte vectors without AVX: inline only, no ABI crossed

namespace inertia {
INERTIA_ISA_BEGIN

typedef double d4 __attribute__((vector_size(32)));
typedef int64_t m4 __attribute__((vector_size(32)));  // lane masks of d4 comparisons: -1 true, 0 false

template <class T>
struct Vec3 {
    T x, y, z;
};
using V3 = Vec3<double>;
using V3x4 = Vec3<d4>;

template <class T>
inline Vec3<T> operator+(const Vec3<T> &a, const Vec3<T> &b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T>
inline Vec3<T> operator-(const Vec3<T> &a, const Vec3<T> &b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T>
inline T dot(const Vec3<T> &a, const Vec3<T> &b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T>
inline Vec3<T> cross(const Vec3<T> &a, const Vec3<T> &b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// Row i of a (n, 3) C-contiguous array.
inline V3 row(const double *xyz, int64_t i = 0) { return {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; }
inline void store(double *out, const V3 &a) { out[0] = a.x, out[1] = a.y, out[2] = a.z; }
// The same on rows of 3 doubles: a . b, n = u x v, out = a - b, |a|.
inline double dot(const double *a, const double *b) { return dot(row(a), row(b)); }
inline void cross(const double *u, const double *v, double *n) { store(n, cross(row(u), row(v))); }
inline void sub(const double *a, const double *b, double *out) { store(out, row(a) - row(b)); }
inline double norm(const double *a) { return std::sqrt(dot(a, a)); }
// Lane l of a V3x4.
inline V3 lane(const V3x4 &a, int l) { return {a.x[l], a.y[l], a.z[l]}; }
// Some lane of a mask is true.
inline bool any(const m4 &x) { return (x[0] | x[1] | x[2] | x[3]) != 0; }
// The first m lanes true.
inline m4 first_lanes(size_t m) { return m4{0, 1, 2, 3} < int64_t(m); }
// The lanes' sum in a fixed order.
inline double lanes_sum(const d4 &x) { return (x[0] + x[1]) + (x[2] + x[3]); }
// How many trues were added into x, a sum of masks (-1 each).
inline int64_t true_count(const m4 &x) { return -(x[0] + x[1] + x[2] + x[3]); }

// Corner k of the m faces f[0..3m) (indices checked), minus p, one lane per face (lanes past m: 0).
inline V3x4 corners(const double *v, const int64_t *f, size_t m, int k, const V3 &p) {
    const double *r[4];
    for (size_t l = 0; l < 4; ++l) r[l] = l < m ? v + 3 * f[3 * l + k] : &p.x;
    return {d4{r[0][0], r[1][0], r[2][0], r[3][0]} - p.x, d4{r[0][1], r[1][1], r[2][1], r[3][1]} - p.y,
            d4{r[0][2], r[1][2], r[2][2], r[3][2]} - p.z};
}

INERTIA_ISA_END
}  // namespace inertia
