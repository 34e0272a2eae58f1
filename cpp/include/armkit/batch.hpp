// Batch loops over many configurations or poses, split across threads deterministically:
// thread t gets the contiguous block [t N / T, (t + 1) N / T), and every item's result
// depends on that item alone, so the answer is the same whatever the thread count.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace armkit {

//: Items below which one thread does the whole batch (starting a thread costs ~20-50 us).
constexpr std::size_t kItemsPerThread = 2048;

// Calls body(begin, end) on blocks of [0, N) in up to `threads` threads (0: all cores).
template <class Body>
void parallel_for(std::size_t N, int threads, Body&& body) {
    // (hardware_concurrency reads /sys on every call, ~10 us: not asked for small batches)
    std::size_t T = N < 2 * kItemsPerThread ? 1
                    : threads > 0           ? std::size_t(threads)
                                            : std::max(1u, std::thread::hardware_concurrency());
    T = std::max<std::size_t>(1, std::min(T, N / kItemsPerThread));
    if (T == 1) {
        body(std::size_t(0), N);
        return;
    }
    std::vector<std::thread> pool;
    pool.reserve(T - 1);
    for (std::size_t t = 1; t < T; ++t)
        pool.emplace_back([&body, t, T, N] { body(t * N / T, (t + 1) * N / T); });
    body(std::size_t(0), N / T);
    for (auto& thread : pool) thread.join();
}

}  // namespace armkit
