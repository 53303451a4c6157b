// Arrays across the boundary: nanobind ndarrays with dtype, shape and contiguity in the type,
// views over them for the kernels, new NumPy arrays owned by Python, and the checks every
// index and count from outside goes through before a kernel uses it.
#pragma once
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <string>

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
// Outputs written in place (no conversion: the caller's own array).
template <class T>
using Out1 = nb::ndarray<T, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
template <class T>
using Out2 = nb::ndarray<T, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
template <class T>
using OutN3 = nb::ndarray<T, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

using Vertices = InN3<double>;  // (V, 3) float64
using Faces = InN3<int64_t>;    // (F, 3) int64

// A NumPy array of `shape`, owned by Python, zero-filled.
template <class T, size_t N>
nb::ndarray<nb::numpy, T, nb::ndim<N>> new_array(const size_t (&shape)[N]) {
    size_t n = 1;
    for (size_t k = 0; k < N; ++k) n *= shape[k];
    T *data = new T[n > 0 ? n : 1]();
    nb::capsule owner(data, [](void *p) noexcept { delete[] static_cast<T *>(p); });
    return nb::ndarray<nb::numpy, T, nb::ndim<N>>(data, N, shape, owner);
}

// The same, of length n.
template <class T>
nb::ndarray<nb::numpy, T, nb::ndim<1>> new_vector(size_t n) {
    return new_array<T, 1>({n});
}

// Every index of `faces` in 0..n_vertices-1, else InputError naming the first bad one.
inline void check_faces(const int64_t *faces, size_t n_faces, size_t n_vertices, const char *what = "faces") {
    const int64_t nv = static_cast<int64_t>(n_vertices);
    for (size_t i = 0; i < 3 * n_faces; ++i) {
        const int64_t k = faces[i];
        if (k < 0 || k >= nv)
            input_error(std::string(what) + "[" + std::to_string(i / 3) + ", " + std::to_string(i % 3) +
                        "] = " + std::to_string(k) + " names no vertex (there are " + std::to_string(n_vertices) +
                        ")");
    }
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
