// Batch loops over many configurations or poses, split across threads: the items are cut into
// pieces that the threads take in turn as they come free (a thread the machine holds back takes
// fewer), and every item's result depends on that item alone (sums over items are of integers,
// or their order is fixed by the caller), so the answer is the same whatever the thread count
// and whichever thread ran which piece.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace armkit {

//: Items below which one thread does the whole batch (starting a thread costs ~20-50 us).
constexpr std::size_t kItemsPerThread = 2048;
//: Pieces per thread: enough that a thread descheduled on a shared machine delays the end of
//: the batch by a small part of it, few enough that taking a piece (an atomic add) costs nothing.
constexpr std::size_t kPiecesPerThread = 16;

// The machine's cores, asked once (glibc reads /sys for it: ~10 us a call).
inline std::size_t all_cores() {
    static const std::size_t cores = std::max(1u, std::thread::hardware_concurrency());
    return cores;
}

// The threads parallel_pieces runs for N items with `threads` asked for (0: all cores), a
// thread for every `per_thread` items at most (kItemsPerThread for cheap items; 1 where one
// item costs more than starting a thread, as a numeric IK solve does).
inline std::size_t batch_threads(std::size_t N, int threads, std::size_t per_thread = kItemsPerThread) {
    if (N < 2 * per_thread) return 1;  // the usual one-pose call: no thread, no core count
    const std::size_t T = threads > 0 ? std::size_t(threads) : all_cores();
    return std::max<std::size_t>(1, std::min(T, N / per_thread));
}

// Calls body(worker, begin, end) on consecutive pieces of [0, N), in up to `threads` threads
// (0: all cores; worker < batch_threads(N, threads, per_thread) names the thread, for scratch
// space of its own). One thread runs body(0, 0, N) once.
template <class Body>
void parallel_pieces(std::size_t N, int threads, Body&& body, std::size_t per_thread = kItemsPerThread) {
    const std::size_t T = batch_threads(N, threads, per_thread);
    if (T == 1) {
        body(std::size_t(0), std::size_t(0), N);
        return;
    }
    const std::size_t piece = std::max(std::max<std::size_t>(1, per_thread / 2), N / (T * kPiecesPerThread) + 1);
    std::atomic<std::size_t> next{0};
    auto work = [&](std::size_t worker) {
        for (std::size_t begin = next.fetch_add(piece); begin < N; begin = next.fetch_add(piece))
            body(worker, begin, std::min(N, begin + piece));
    };
    std::vector<std::thread> pool;
    pool.reserve(T - 1);
    for (std::size_t t = 1; t < T; ++t) pool.emplace_back(work, t);
    work(0);
    for (auto& thread : pool) thread.join();
}

// Calls body(begin, end) on pieces of [0, N) in up to `threads` threads (0: all cores).
template <class Body>
void parallel_for(std::size_t N, int threads, Body&& body, std::size_t per_thread = kItemsPerThread) {
    parallel_pieces(
        N, threads, [&body](std::size_t, std::size_t begin, std::size_t end) { body(begin, end); }, per_thread);
}

}  // namespace armkit
