// Bindings of the integrals family (inertia._ext.integrals): mesh integrals, the clean-solid
// pass.  Outputs are allocated with the GIL held; the kernels run without it, those of
// kernels.hpp through the table of the instruction set the CPU chose (dispatch.cpp).
#include <nanobind/stl/optional.h>

#include "common/arrays.hpp"
#include "integrals/kernels.hpp"
#include "integrals/sums.hpp"

namespace {

using namespace inertia;
using Adjacency = OutN3<int64_t>;

V3 point3(const In1<double> &p, const char *what) {
    check_length(p.shape(0), 3, what);
    return row(p.data(), 0);
}

template <bool Shell>
auto sums(const Vertices &v, const Faces &f, const In1<double> &p) {
    const V3 q = point3(p, "p");
    const double at[3] = {q.x, q.y, q.z};
    auto out = new_vector<double>(10);
    bool ok;
    {
        nb::gil_scoped_release unlocked;
        const IntegralKernels &k = integral_kernels();
        ok = (Shell ? k.shell_sums : k.solid_sums)(v.data(), v.shape(0), f.data(), f.shape(0), at, out.data());
    }
    if (!ok) check_faces(f.data(), f.shape(0), v.shape(0));  // throws, naming the first bad index
    return out;
}

}  // namespace

void bind_integrals(nb::module_ &m) {
    m.attr("SUM_BLOCK") = SUM_BLOCK;
    m.attr("SUM_CHUNK") = SUM_CHUNK;
    m.def("bbox_center", [](const Vertices &v) {
        check_at_least(v.shape(0), 1, "vertices");
        const V3 c = bbox_center(v.data(), v.shape(0));
        auto out = new_vector<double>(3);
        out.data()[0] = c.x, out.data()[1] = c.y, out.data()[2] = c.z;
        return out;
    }, "Center (3,) of the axis-aligned bounding box of vertices (V >= 1, 3).");
    m.def("solid_sums", &sums<false>, nb::arg("vertices"), nb::arg("faces"), nb::arg("p"),
          "Unscaled volume sums (10,) about p: sum det, det s (3), det Q (xx yy zz xy yz zx); /6, /24, /120.");
    m.def("shell_sums", &sums<true>, nb::arg("vertices"), nb::arg("faces"), nb::arg("p"),
          "Unscaled surface sums (10,) about p: sum w, w s (3), w Q with w = 2 x area; /2, /6, /24.");
    m.def(
        "clean_solid",
        [](const Vertices &v, const Faces &f, double area_rtol, double limit,
           std::optional<Adjacency> adj) -> nb::object {
            if (adj && adj->shape(0) != f.shape(0) && adj->shape(0) != 0)
                input_error("adj has " + std::to_string(adj->shape(0)) + " rows, expected 0 or " +
                            std::to_string(f.shape(0)) + " (one per face)");
            auto out = new_vector<double>(15);
            bool ok;
            {
                nb::gil_scoped_release unlocked;
                ok = integral_kernels().clean_solid(v.data(), v.shape(0), f.data(), f.shape(0), area_rtol, limit,
                                                    out.data(), adj && adj->shape(0) ? adj->data() : nullptr);
            }
            return ok ? nb::cast(out) : nb::none();
        },
        nb::arg("vertices"), nb::arg("faces"), nb::arg("area_rtol"), nb::arg("limit") = INFINITY,
        nb::arg("adj") = nb::none(),
        "One closed, consistently wound, outward, non-degenerate shell?  Its (15,) sums (10 volume sums "
        "about p, 2 x area, p (3), 1 if proved star-shaped from p) or None; adj (F, 3) int64 receives each "
        "edge's twin face when the shell is not proved star-shaped.");
}
