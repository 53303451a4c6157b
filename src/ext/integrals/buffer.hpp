// Scratch arrays of a kernel, uninitialised.  Large ones are asked for in transparent huge pages
// (Linux madvise), as NumPy does for its own arrays: the first touch of a fresh 4 KiB page costs
// about as much as the work done on it (measured: 18 ms of a 60 ms pass over 1.3M faces).
#pragma once
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace inertia {

struct FreeBuffer {
    void operator()(void *p) const noexcept { std::free(p); }
};
template <class T>
using Buffer = std::unique_ptr<T[], FreeBuffer>;

template <class T>
Buffer<T> scratch(size_t n) {
    constexpr size_t huge = size_t(1) << 21;
    size_t bytes = (n > 0 ? n : 1) * sizeof(T);
    void *p;
    if (bytes >= 2 * huge) {
        bytes = (bytes + huge - 1) & ~(huge - 1);
        p = std::aligned_alloc(huge, bytes);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        if (p) madvise(p, bytes, MADV_HUGEPAGE);
#endif
    } else {
        p = std::malloc(bytes);
    }
    if (!p) throw std::bad_alloc();
    return Buffer<T>(static_cast<T *>(p));
}

}  // namespace inertia
