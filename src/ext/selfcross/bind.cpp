// Bindings of the selfcross family (inertia._ext.selfcross).
#include "common/arrays.hpp"

void bind_selfcross(nb::module_ &m) { (void)m; }
