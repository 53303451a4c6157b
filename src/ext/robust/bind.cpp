// Bindings of the robust family (inertia._ext.robust): each job's file binds its own kernels.
#include "common/arrays.hpp"

namespace inertia::robust {
void bind_topo(nb::module_& m);
void bind_cuts(nb::module_& m);
void bind_clip(nb::module_& m);
void bind_caps(nb::module_& m);
}  // namespace inertia::robust

void bind_robust(nb::module_& m) {
    inertia::robust::bind_topo(m);
    inertia::robust::bind_cuts(m);
    inertia::robust::bind_clip(m);
    inertia::robust::bind_caps(m);
}
