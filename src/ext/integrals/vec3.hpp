// 3-vectors for the per-face arithmetic, of doubles (V3) or of 4 faces at once (V3x4: one lane
// per face, GCC/Clang vector extensions; a build without AVX runs each as two SSE2 halves).
// Every operation is the plain IEEE expression written left to right, lane by lane (no fused
// multiply-add: -ffp-contract=off), so a lane gives the bits its scalar twin would.
#pragma once
#include <cstddef>
#include <cstdint>

#pragma GCC diagnostic ignored "-Wpsabi"  // 32-byte vectors without AVX: inline only, no ABI crossed

namespace inertia {

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
inline V3 row(const double *xyz, int64_t i) { return {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; }
// Lane l of a V3x4.
inline V3 lane(const V3x4 &a, int l) { return {a.x[l], a.y[l], a.z[l]}; }
// Some lane of a mask is true.
inline bool any(const m4 &x) { return (x[0] | x[1] | x[2] | x[3]) != 0; }
// The first m lanes true.
inline m4 first_lanes(size_t m) { return m4{0, 1, 2, 3} < int64_t(m); }
// The lanes' sum in a fixed order.
inline double lanes_sum(const d4 &x) { return (x[0] + x[1]) + (x[2] + x[3]); }

}  // namespace inertia
