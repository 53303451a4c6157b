// 3-vectors for the per-face arithmetic, of doubles (V3) or of 4 faces at once (V3x4: one lane
// per face, GCC/Clang vector extensions; a build without AVX runs each as two SSE2 halves).
// Every operation is the plain IEEE expression written left to right, lane by lane (no fused
// multiply-add: -ffp-contract=off), so a lane gives the bits its scalar twin would.
#pragma once
#include <cstdint>

#pragma GCC diagnostic ignored "-Wpsabi"  // 32-byte vectors without AVX: inline only, no ABI crossed

namespace inertia {

typedef double d4 __attribute__((vector_size(32)));

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
// The lanes' sum in a fixed order.
inline double lanes_sum(const d4 &x) { return (x[0] + x[1]) + (x[2] + x[3]); }

}  // namespace inertia
