// Open-addressing hash tables (linear probing, power-of-two capacity), the buffers and the
// union-find that the weld, the near merge and the components share.
#pragma once
#include <cstdint>

#include "common/buffer.hpp"
#include "common/union_find.hpp"

namespace inertia::topology {

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

}  // namespace inertia::topology
