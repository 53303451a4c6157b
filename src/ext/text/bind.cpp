// Bindings of the text family (inertia._ext.text).
#include "common/arrays.hpp"

void bind_text(nb::module_ &m) { (void)m; }
