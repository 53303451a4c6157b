// Union-find with the lowest index as root (roots are group minima), path halving.
#pragma once

#include "common/isa.hpp"

namespace inertia {
INERTIA_ISA_BEGIN

template <class I>
I find_root(I *parent, I i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

// Join the sets of a and b (the lower root wins); true if they were apart.
template <class I>
bool union_low(I *parent, I a, I b) {
    const I ra = find_root(parent, a), rb = find_root(parent, b);
    if (ra == rb) return false;
    if (ra < rb)
        parent[rb] = ra;
    else
        parent[ra] = rb;
    return true;
}

INERTIA_ISA_END
}  // namespace inertia
