// The integrals kernels that run on every mesh (the clean-solid pass, the volume and surface
// sums), compiled once per instruction set (CMakeLists.txt, common/isa.hpp): no nanobind here,
// and no std container but Vec (whose allocator lives in this variant's namespace).
#include "integrals/kernels.hpp"

#include "common/isa.hpp"
#include "integrals/clean_solid.hpp"
#include "integrals/sums.hpp"

namespace inertia {
INERTIA_ISA_BEGIN

namespace {

template <bool Shell>
bool sums(const double *v, size_t nv, const int64_t *faces, size_t nf, const double *p, double *out) {
    return mesh_sums<Shell>(v, nv, faces, nf, row(p), out);
}

}  // namespace

INERTIA_ISA_END

// This variant's table: inertia::integral_kernels_<tag>, listed by dispatch.cpp.
extern const IntegralKernels INERTIA_CAT(integral_kernels_, INERTIA_ISA) = {&clean_solid, &sums<false>, &sums<true>};

}  // namespace inertia
