// Shared pieces of the robust family (inertia._ext.robust): the mesh view, solid angles and
// tetrahedron sums, index checks, fixed-partition threads and vectors handed to NumPy.
// Conventions: triangles are index triples into V (N, 3); `eps` is a length; every
// intersection test is conservative (true = "may cut" within eps), so that false is safe.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "common/arrays.hpp"

namespace inertia::robust {

constexpr double PI = 3.141592653589793;
constexpr double FOUR_PI = 4.0 * PI;
constexpr double TWO_PI = 2.0 * PI;
constexpr double INF = INFINITY;

template <class T>
using In3x3 = nb::ndarray<const T, nb::shape<-1, 3, 3>, nb::c_contig, nb::device::cpu>;
template <class T>
using InN4 = nb::ndarray<const T, nb::shape<-1, 4>, nb::c_contig, nb::device::cpu>;
template <class T>
using OutN3 = nb::ndarray<T, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

// A std::vector handed to NumPy without a copy (the capsule owns it).
template <class T, size_t N>
nb::ndarray<nb::numpy, T, nb::ndim<N>> to_numpy(std::vector<T>&& v, const size_t (&shape)[N]) {
    if (v.empty()) v.reserve(1);
    auto* owned = new std::vector<T>(std::move(v));
    nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
    return nb::ndarray<nb::numpy, T, nb::ndim<N>>(owned->data(), N, shape, owner);
}

// Items 0..n-1 in fixed contiguous ranges, one per thread (threads <= 0: one per core; fewer
// when a range would hold less than `grain` items).  Callers write per-item slots only, so the
// result does not depend on the number of threads.
template <class Fn>
void parallel_for(size_t n, int threads, size_t grain, Fn&& fn) {
    size_t t = threads > 0 ? size_t(threads) : std::max(1u, std::thread::hardware_concurrency());
    t = std::min(t, (n + grain - 1) / std::max<size_t>(grain, 1));
    if (t <= 1) {
        if (n) fn(size_t(0), n);
        return;
    }
    std::exception_ptr err;
    std::mutex mu;
    auto run = [&](size_t k) {
        try {
            fn(n * k / t, n * (k + 1) / t);
        } catch (...) {
            std::lock_guard<std::mutex> lock(mu);
            if (!err) err = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    for (size_t k = 1; k < t; ++k) pool.emplace_back(run, k);
    run(0);
    for (auto& th : pool) th.join();
    if (err) std::rethrow_exception(err);
}

// Every a[i] in [lo, hi), else InputError naming the array, the row and the value.
inline void check_range(const int64_t* a, size_t n, int64_t lo, int64_t hi, const char* what) {
    for (size_t i = 0; i < n; ++i)
        if (a[i] < lo || a[i] >= hi)
            input_error(std::string(what) + "[" + std::to_string(i) + "] = " + std::to_string(a[i]) + " is outside [" +
                        std::to_string(lo) + ", " + std::to_string(hi) + ")");
}

// A CSR pointer of `rows` rows over `items` entries: starts at 0, never decreases, ends at items.
inline void check_ptr(const int64_t* ptr, size_t len, size_t rows, size_t items, const char* what) {
    check_length(len, rows + 1, what);
    if (ptr[0] != 0 || ptr[rows] != int64_t(items))
        input_error(std::string(what) + " must run from 0 to " + std::to_string(items));
    for (size_t i = 0; i < rows; ++i)
        if (ptr[i + 1] < ptr[i]) input_error(std::string(what) + " decreases at " + std::to_string(i));
}

// The closed chain: vertices, faces (checked), multiplicities.
struct Mesh {
    const double* V;
    const int64_t* F;
    const double* M;
    size_t nv, nf;
    const double* at(int64_t f, int k) const { return V + 3 * F[3 * f + k]; }
    void load(int64_t f, double T[3][3]) const {
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) T[k][c] = at(f, k)[c];
    }
};

inline Mesh mesh_of(const Vertices& V, const Faces& F, const In1<double>* M = nullptr) {
    check_faces(F.data(), F.shape(0), V.shape(0));
    if (M) check_length(M->shape(0), F.shape(0), "multiplicities");
    return {V.data(), F.data(), M ? M->data() : nullptr, V.shape(0), F.shape(0)};
}

inline double dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline void cross(const double* u, const double* v, double* n) {
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}
inline void sub(const double* a, const double* b, double* out) {
    for (int c = 0; c < 3; ++c) out[c] = a[c] - b[c];
}
inline double norm(const double* a) { return std::sqrt(dot(a, a)); }

// Van Oosterom-Strackee solid angle of the triangle (a, b, c) - p (positive from behind):
// tan(Omega / 2) = a . (b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|).
inline double solid_angle(const double* A, const double* B, const double* C, double px, double py, double pz) {
    const double ax = A[0] - px, ay = A[1] - py, az = A[2] - pz;
    const double bx = B[0] - px, by = B[1] - py, bz = B[2] - pz;
    const double cx = C[0] - px, cy = C[1] - py, cz = C[2] - pz;
    const double la = std::sqrt(ax * ax + ay * ay + az * az), lb = std::sqrt(bx * bx + by * by + bz * bz),
                 lc = std::sqrt(cx * cx + cy * cy + cz * cz);
    const double det = ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx);
    const double den = la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (bx * cx + by * cy + bz * cz) * la +
                       (cx * ax + cy * ay + cz * az) * lb;
    return 2.0 * std::atan2(det, den);
}
inline double solid_angle(const Mesh& m, int64_t f, double px, double py, double pz) {
    return solid_angle(m.at(f, 0), m.at(f, 1), m.at(f, 2), px, py, pz);
}

// acc (10,) += weight x the signed tetrahedron (0, a, b, c) integrals times 6, 24 (x3), 120 (x6):
// volume, int y (3), int y y^T (xx, yy, zz, xy, xz, yz).
inline void tetra_add(double* acc, double weight, const double* a, const double* b, const double* c) {
    const double det = weight * (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                                 a[2] * (b[0] * c[1] - b[1] * c[0]));
    const double s[3] = {a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]};
    acc[0] += det;
    for (int i = 0; i < 3; ++i) acc[1 + i] += det * s[i];
    static constexpr int P[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
    for (int k = 0; k < 6; ++k) {
        const int i = P[k][0], j = P[k][1];
        acc[4 + k] += det * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
    }
}

// out (13,) += bounds of the tetrahedron (0, a, b, c) integrals of |1|, |y_j|, |y_j y_k|:
// |V|, |V| max|y_j|, |V| max|y_j| max|y_k| (the largest |y_j| is at a corner).
inline void tetra_abs(double* out, double weight, const double* a, const double* b, const double* c) {
    const double vol = std::abs(a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                                a[2] * (b[0] * c[1] - b[1] * c[0])) /
                       6.0 * weight;
    double m[3];
    for (int j = 0; j < 3; ++j) m[j] = std::max(std::abs(a[j]), std::max(std::abs(b[j]), std::abs(c[j])));
    out[0] += vol;
    for (int j = 0; j < 3; ++j) out[1 + j] += vol * m[j];
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) out[4 + 3 * j + k] += vol * m[j] * m[k];
}

}  // namespace inertia::robust
