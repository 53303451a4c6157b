// Open-addressing hash tables (linear probing, power-of-two capacity) and union-find with the
// lowest index as root: the pieces the weld, the near merge and the components share.
#pragma once
#include <cstdint>
#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace inertia::topology {

// An allocator that leaves new elements uninitialised (no zero fill of arrays the kernels write
// whole before reading: on a million-face mesh that fill is a pass over tens of megabytes).
template <class T>
struct uninit_alloc : std::allocator<T> {
    using std::allocator<T>::allocator;
    template <class U>
    struct rebind {
        using other = uninit_alloc<U>;
    };
    template <class U>
    void construct(U *p) noexcept {
        ::new (static_cast<void *>(p)) U;
    }
    template <class U, class... A>
    void construct(U *p, A &&...args) {
        ::new (static_cast<void *>(p)) U(std::forward<A>(args)...);
    }
};
template <class T>
using Vec = std::vector<T, uninit_alloc<T>>;

// 64-bit hash of three 64-bit words (multiply, xor, fold the high bits down).
inline uint64_t mix3(uint64_t a, uint64_t b, uint64_t c) {
    uint64_t h = (a * 0x9E3779B97F4A7C15ull) ^ (b * 0xC2B2AE3D27D4EB4Full) ^ (c * 0x165667B19E3779F9ull);
    h ^= h >> 29;
    h ^= h >> 32;
    return h;
}

// A power of two >= 4 n and >= 16: a table for n keys, filled a quarter at most.
inline uint64_t capacity(uint64_t n) {
    uint64_t cap = 16;
    while (cap < 4 * n) cap *= 2;
    return cap;
}

// Root of i, halving the path as it goes.
inline int64_t find_root(Vec<int64_t> &parent, int64_t i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

// Join the sets of a and b; the lower root becomes the root, so every root is its set's minimum.
inline void union_low(Vec<int64_t> &parent, int64_t a, int64_t b) {
    const int64_t ra = find_root(parent, a), rb = find_root(parent, b);
    if (ra < rb) parent[rb] = ra;
    else if (rb < ra) parent[ra] = rb;
}

}  // namespace inertia::topology
