// Bindings of the dynamics family (inertia._ext.dynamics).
#include <nanobind/stl/tuple.h>

#include "dynamics/kernels.hpp"
#include "dynamics/gyrostat.hpp"
#include "dynamics/steps.hpp"

namespace dyn = inertia::dynamics;

void bind_dynamics(nb::module_ &m) {
    using namespace nb::literals;
    const auto nogil = nb::call_guard<nb::gil_scoped_release>();
    m.def("advance", &dyn::advance, "method"_a, "q"_a, "m"_a, "moments"_a, "torque"_a, "counts"_a, "hs"_a, "slots"_a,
          "qs"_a, "ws"_a, "stop_if_not_finite"_a, nogil,
          "Advance bodies (B) over segments of fixed steps in place; (failed body or -1, steps done, kind, "
          "Newton residual).");
    m.def("rollout", &dyn::rollout, "method"_a, "x0"_a, "u"_a, "moments"_a, "mass"_a, "frame"_a, "gravity"_a, "h"_a,
          "n_steps"_a, "save_every"_a, "body_force"_a, "threads"_a, "out"_a, "status"_a, nogil,
          "6-DOF rollout of N bodies into out (S, N, 13); status[b] = the step where body b's Newton failed, or -1.");
    m.def("gyro_rollout", &dyn::gyro_rollout, "method"_a, "x0"_a, "plant"_a, "control"_a, "gravity"_a, "h"_a,
          "substeps"_a, "n_steps"_a, "save_every"_a, "threads"_a, "out"_a, "tilt"_a, nogil,
          "Closed-loop rollout of N gyrostats (principal frames) into out (S, N, 13 + n) and tilt (S, N).");
    m.def("gyro_jacobians", &dyn::gyro_jacobians, "method"_a, "x"_a, "u"_a, "plant"_a, "gravity"_a, "h"_a,
          "substeps"_a, "A"_a, "B"_a, nogil, "Complex-step error-state Jacobians of the gyrostat step into A, B.");
    m.attr("MAX_WHEELS") = dyn::MAX_WHEELS;
    m.attr("METHODS") = nb::make_tuple("euler_explicit", "euler_implicit", "rk4", "splitting", "dmv", "dmv4",
                                       "midpoint");
    m.attr("NEWTON_MAX_ITER") = dyn::NEWTON_MAX_ITER;
}
