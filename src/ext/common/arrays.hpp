// Arrays across the boundary: nanobind ndarrays with dtype, shape and contiguity in the type,
// views over them for the kernels, new NumPy arrays owned by Python (fresh, or a kernel's vector
// handed over), and the checks every index and count from outside goes through before use.
#pragma once
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

#include "common/errors.hpp"

namespace nb = nanobind;

namespace inertia {

// Read-only inputs (a copy is made by nanobind when dtype or layout differ).
template <class T>
using In1 = nb::ndarray<const T, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
template <class T>
using In2 = nb::ndarray<const T, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
template <class T>
using InN3 = nb::ndarray<const T, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
template <class T>
using In3x3 = nb::ndarray<const T, nb::shape<-1, 3, 3>, nb::c_contig, nb::device::cpu>;  // (N, 3, 3)
// Outputs written in place (no conversion: the caller's own array).
template <class T>
using Out1 = nb::ndarray<T, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
template <class T>
using Out2 = nb::ndarray<T, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
template <class T>
using OutN3 = nb::ndarray<T, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

using Vertices = InN3<double>;  // (V, 3) float64
using Faces = InN3<int64_t>;    // (F, 3) int64

template <class T, size_t N>
using NpArray = nb::ndarray<nb::numpy, T, nb::ndim<N>>;

// A vector (std::vector or Vec) handed to NumPy without a copy: the array owns it from then on.
template <class V, size_t N>
NpArray<typename V::value_type, N> to_numpy(V &&v, const size_t (&shape)[N]) {
    if (v.empty()) v.reserve(1);  // a data pointer even when empty
    auto *owned = new V(std::move(v));
    nb::capsule owner(owned, [](void *p) noexcept { delete static_cast<V *>(p); });
    return NpArray<typename V::value_type, N>(owned->data(), N, shape, owner);
}

// A NumPy array of `shape`, owned by Python, zero-filled.
template <class T, size_t N>
NpArray<T, N> new_array(const size_t (&shape)[N]) {
    size_t n = 1;
    for (size_t k = 0; k < N; ++k) n *= shape[k];
    T *data = new T[n > 0 ? n : 1]();
    nb::capsule owner(data, [](void *p) noexcept { delete[] static_cast<T *>(p); });
    return NpArray<T, N>(data, N, shape, owner);
}

// The same, of length n.
template <class T>
NpArray<T, 1> new_vector(size_t n) {
    return new_array<T, 1>({n});
}

// Every a[i] in [lo, hi): one min/max pass, which the compiler vectorises (the loops that name a
// bad entry run only when there is one).
inline bool all_in(const int64_t *a, size_t n, int64_t lo, int64_t hi) {
    int64_t mn = lo, mx = lo;
    for (size_t i = 0; i < n; ++i) mn = std::min(mn, a[i]), mx = std::max(mx, a[i]);
    return n == 0 || (mn >= lo && mx < hi);
}

// Every entry of the (rows, 3) index array `a` in [0, limit), else InputError naming the first
// bad one: "faces[3, 1] = 42 names no vertex (there are 42)", with `noun` and `count`.
inline void check_index_rows(const int64_t *a, size_t rows, size_t limit, const char *what, const char *noun,
                             size_t count) {
    if (all_in(a, 3 * rows, 0, int64_t(limit))) return;
    for (size_t i = 0; i < 3 * rows; ++i)
        if (a[i] < 0 || a[i] >= int64_t(limit))
            input_error(std::string(what) + "[" + std::to_string(i / 3) + ", " + std::to_string(i % 3) + "] = " +
                        std::to_string(a[i]) + " names no " + noun + " (there are " + std::to_string(count) + ")");
}

// Every index of `faces` in 0..n_vertices-1, else InputError naming the first bad one.
inline void check_faces(const int64_t *faces, size_t n_faces, size_t n_vertices, const char *what = "faces") {
    check_index_rows(faces, n_faces, n_vertices, what, "vertex", n_vertices);
}

// Every a[i] in [lo, hi), else InputError naming the array, the entry and the value.
inline void check_range(const int64_t *a, size_t n, int64_t lo, int64_t hi, const char *what) {
    if (all_in(a, n, lo, hi)) return;
    for (size_t i = 0; i < n; ++i)
        if (a[i] < lo || a[i] >= hi)
            input_error(std::string(what) + "[" + std::to_string(i) + "] = " + std::to_string(a[i]) + " is outside [" +
                        std::to_string(lo) + ", " + std::to_string(hi) + ")");
}

// A length that must equal `expected`, else InputError naming the argument.
inline void check_length(size_t got, size_t expected, const char *what) {
    if (got != expected)
        input_error(std::string(what) + " has length " + std::to_string(got) + ", expected " +
                    std::to_string(expected));
}

// A length of at least `minimum`.
inline void check_at_least(size_t got, size_t minimum, const char *what) {
    if (got < minimum)
        input_error(std::string(what) + " has length " + std::to_string(got) + ", needs at least " +
                    std::to_string(minimum));
}

}  // namespace inertia
