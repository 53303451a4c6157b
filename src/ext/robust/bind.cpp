// Bindings of the robust family (inertia._ext.robust).
#include "common/arrays.hpp"

void bind_robust(nb::module_ &m) { (void)m; }
