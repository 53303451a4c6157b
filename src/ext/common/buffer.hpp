// Vec<T>: the one buffer type of the kernels, a std::vector whose new elements are left
// uninitialised (no zero fill of arrays a kernel writes whole before reading: on a million-face
// mesh that fill is a pass over tens of megabytes).  Blocks of 4 MiB and more are asked for in
// transparent huge pages (Linux madvise), as NumPy does for its own arrays: the first touch of a
// fresh 4 KiB page costs about as much as the work done on it (18 ms of a 60 ms pass, 1.3M faces).
#pragma once
#include <cstddef>
#include <cstdlib>
#include <new>
#include <utility>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "common/isa.hpp"

namespace inertia {
INERTIA_ISA_BEGIN

template <class T>
struct uninit_alloc {
    using value_type = T;
    uninit_alloc() = default;
    template <class U>
    uninit_alloc(const uninit_alloc<U> &) noexcept {}
    T *allocate(size_t n) {
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
        return static_cast<T *>(p);
    }
    void deallocate(T *p, size_t) noexcept { std::free(p); }
    template <class U>
    void construct(U *p) noexcept {
        ::new (static_cast<void *>(p)) U;
    }
    template <class U, class... A>
    void construct(U *p, A &&...args) {
        ::new (static_cast<void *>(p)) U(std::forward<A>(args)...);
    }
    template <class U>
    bool operator==(const uninit_alloc<U> &) const noexcept { return true; }
    template <class U>
    bool operator!=(const uninit_alloc<U> &) const noexcept { return false; }
};

template <class T>
using Vec = std::vector<T, uninit_alloc<T>>;

INERTIA_ISA_END
}  // namespace inertia
