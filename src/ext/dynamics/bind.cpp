// Bindings of the dynamics family (inertia._ext.dynamics).
#include "common/arrays.hpp"

void bind_dynamics(nb::module_ &m) { (void)m; }
