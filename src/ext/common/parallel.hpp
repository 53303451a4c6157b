// Items 0..n-1 in fixed contiguous ranges, one per thread (threads <= 0: one per core; fewer when
// a range would hold less than `grain` items).  Callers write per-item slots only, so the result
// does not depend on the number of threads.  An exception in a range is rethrown here.
#pragma once
#include <algorithm>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace inertia {

template <class Fn>
void parallel_for(size_t n, int threads, size_t grain, Fn &&fn) {
    size_t t = threads > 0 ? size_t(threads) : std::max(1u, std::thread::hardware_concurrency());
    t = std::min(t, (n + grain - 1) / std::max<size_t>(grain, 1));
    if (t <= 1) {
        if (n) fn(size_t(0), n);
        return;
    }
    std::exception_ptr err;
    std::mutex mu;
    auto run = [&](size_t k) {
        try {
            fn(n * k / t, n * (k + 1) / t);
        } catch (...) {
            std::lock_guard<std::mutex> lock(mu);
            if (!err) err = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    for (size_t k = 1; k < t; ++k) pool.emplace_back(run, k);
    run(0);
    for (auto &th : pool) th.join();
    if (err) std::rethrow_exception(err);
}

}  // namespace inertia
