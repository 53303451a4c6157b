// Bindings of the integrals family (inertia._ext.integrals).
#include "common/arrays.hpp"

void bind_integrals(nb::module_ &m) { (void)m; }
