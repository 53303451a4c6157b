// The entry points of the integrals kernels compiled once per instruction set (kernels.cpp;
// common/isa.hpp), which bind.cpp calls through the table the CPU chose.
#pragma once
#include <cstddef>
#include <cstdint>

namespace inertia {

struct IntegralKernels {
    // clean_solid of clean_solid.hpp
    bool (*clean_solid)(const double *v, size_t nv, const int64_t *faces, size_t nf, double area_rtol, double limit,
                        double *out, int64_t *adj);
    // mesh_sums<false> and mesh_sums<true> of sums.hpp about the point p (3); false at a face
    // index outside [0, nv), which the caller then names (check_faces)
    bool (*solid_sums)(const double *v, size_t nv, const int64_t *faces, size_t nf, const double *p, double *out);
    bool (*shell_sums)(const double *v, size_t nv, const int64_t *faces, size_t nf, const double *p, double *out);
};

// The table of the variant in use (dispatch.cpp).
const IntegralKernels &integral_kernels();

}  // namespace inertia
