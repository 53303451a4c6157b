// Bindings of the topology family (inertia._ext.topology).
#include "common/arrays.hpp"

void bind_topology(nb::module_ &m) { (void)m; }
