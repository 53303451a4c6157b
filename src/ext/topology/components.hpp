// Connected components of an undirected graph, numbered in order of their lowest node (as
// scipy.sparse.csgraph.connected_components numbers them).
#pragma once
#include <cstdint>
#include <vector>

#include "topology/hash.hpp"

namespace inertia::topology {

// labels[i] for nodes 0..n-1 joined by the m edges a[e] - b[e] (indices checked by the caller);
// returns the number of components.
inline int64_t connected_components(size_t n, const int64_t *a, const int64_t *b, size_t m, int64_t *labels) {
    Vec<int64_t> parent(n);
    for (size_t i = 0; i < n; ++i) parent[i] = int64_t(i);
    for (size_t e = 0; e < m; ++e) union_low(parent.data(), a[e], b[e]);
    int64_t count = 0;
    for (size_t i = 0; i < n; ++i)   // a root is its component's lowest node: it comes first
        labels[i] = parent[i] == int64_t(i) ? count++ : labels[find_root(parent.data(), int64_t(i))];
    return count;
}

}  // namespace inertia::topology
