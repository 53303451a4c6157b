// Bindings of the principal family (inertia._ext.principal): the canonical principal frame of
// (N, 3, 3) symmetric matrices.
#include <nanobind/stl/tuple.h>

#include "common/arrays.hpp"
#include "principal/canonical.hpp"

void bind_principal(nb::module_ &m) {
    using namespace inertia;
    using namespace nb::literals;
    m.def("canonical_frames", [](In3x3<double> I, double rtol) {
        const size_t n = I.shape(0);
        auto moments = new_array<double, 2>({n, 3});
        auto R = new_array<double, 3>({n, 3, 3});
        auto repeated = new_vector<int8_t>(n);
        {
            nb::gil_scoped_release unlocked;
            for (size_t i = 0; i < n; ++i)
                repeated.data()[i] = int8_t(principal::canonical_frame(I.data() + 9 * i, rtol, moments.data() + 3 * i,
                                                                        R.data() + 9 * i));
        }
        return nb::make_tuple(moments, R, repeated);
    }, "inertia"_a, "rtol"_a,
          "(moments (N, 3) ascending, R_body_principal (N, 3, 3), repeated (N,) int8: bit 1 I1 == I2, bit 2\n"
          "I2 == I3 within rtol times the largest) of the symmetric parts of (N, 3, 3) matrices, in canonical form.");
}
