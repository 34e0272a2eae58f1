// Reachability counting in one pass: configurations drawn uniformly inside a joint box (or
// given), their tool positions, the voxel each falls in and the hits per voxel, with no
// per-configuration arrays (armkit/workspace/reachability.py is the Python side).
//
// Random stream: configuration i of a batch seeded `seed` draws its n joint values from
// splitmix64 started at item_seed(seed, i) (a counter-based generator: each configuration's
// values depend on (seed, i) alone), so the samples, and the counts, are the same whatever
// the thread split.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>

#include "armkit/batch.hpp"
#include "armkit/fk.hpp"
#include "armkit/linalg.hpp"
#include "armkit/random.hpp"

namespace armkit {

// A voxel grid: voxel (i, j, k) spans lower + [i, i + 1) * resolution (and so on per axis);
// flat index (i * shape[1] + j) * shape[2] + k (C order, as numpy.ravel_multi_index).
struct VoxelGrid {
    double lower[3];
    double resolution;
    std::int64_t shape[3];

    std::int64_t size() const { return shape[0] * shape[1] * shape[2]; }

    // The flat index of the voxel holding p, or -1 outside the grid: floor((p - lower) / h)
    // per axis, the same operations as armkit.workspace.Grid.flat_index.
    std::int64_t flat_index(double x, double y, double z) const {
        const double p[3] = {x, y, z};
        std::int64_t flat = 0;
        for (int a = 0; a < 3; ++a) {
            const double cell = std::floor((p[a] - lower[a]) / resolution);
            if (!(cell >= 0.0 && cell < double(shape[a]))) return -1;
            flat = flat * shape[a] + std::int64_t(cell);
        }
        return flat;
    }
};

// Joint values q (n) of configuration `index` of the batch seeded `seed`, uniform in
// [low, high) per joint: 53 random bits scaled, as Random::uniform.
inline void uniform_configuration(std::uint64_t seed, std::uint64_t index, int n, const double* low,
                                  const double* high, double* q) {
    std::uint64_t state = item_seed(seed, index);
    for (int j = 0; j < n; ++j)
        q[j] = low[j] + (high[j] - low[j]) * (double(splitmix64(state) >> 11) * 0x1.0p-53);
}

// Hits per voxel and samples outside the grid of one thread's share of a batch.
struct VoxelCounts {
    std::int64_t* hits;  // grid.size() counters
    std::int64_t outside = 0;

    // Counts the tool positions of kFkBlock configurations q (kFkBlock x n, row-major).
    void add_block(const Chain& chain, const VoxelGrid& grid, const double* q) {
        double T[16 * kFkBlock];
        tool_poses_block(chain, q, T);
        for (int b = 0; b < kFkBlock; ++b) add(grid.flat_index(T[16 * b + 3], T[16 * b + 7], T[16 * b + 11]));
    }

    // Counts the tool position of one configuration q (n).
    void add_one(const Chain& chain, const VoxelGrid& grid, const double* q) {
        const Pose T = tool_pose(chain, q);
        add(grid.flat_index(T(0, 3), T(1, 3), T(2, 3)));
    }

    void add(std::int64_t flat) {
        if (flat < 0)
            ++outside;
        else
            ++hits[flat];
    }
};

// Runs fill(counts, begin, end) for items [0, N) split over up to `threads` threads (as
// parallel_for), each thread counting into its own array; the arrays are then added into
// hits (grid.size()) in the order of their blocks. Returns the samples outside the grid.
template <class Fill>
std::int64_t count_voxels(std::size_t N, const VoxelGrid& grid, std::int64_t* hits, int threads, Fill&& fill) {
    std::mutex lock;
    std::vector<std::pair<std::size_t, std::vector<std::int64_t>>> shares;  // (begin, hits) of other threads
    std::int64_t outside = 0;
    parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
        if (begin == 0) {  // the first block counts straight into hits
            VoxelCounts counts{hits};
            fill(counts, begin, end);
            const std::lock_guard<std::mutex> guard(lock);
            outside += counts.outside;
            return;
        }
        std::vector<std::int64_t> own(std::size_t(grid.size()), 0);
        VoxelCounts counts{own.data()};
        fill(counts, begin, end);
        const std::lock_guard<std::mutex> guard(lock);
        outside += counts.outside;
        shares.emplace_back(begin, std::move(own));
    });
    std::sort(shares.begin(), shares.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& share : shares)
        for (std::size_t v = 0; v < share.second.size(); ++v) hits[v] += share.second[v];
    return outside;
}

// Adds to hits the tool positions of configurations [first, first + N) of the batch seeded
// `seed`, uniform in the box [low, high) (n values each); returns the samples outside the grid.
inline std::int64_t count_uniform(const Chain& chain, const double* low, const double* high, std::uint64_t seed,
                                  std::uint64_t first, std::size_t N, const VoxelGrid& grid, std::int64_t* hits,
                                  int threads) {
    const int n = chain.n;
    return count_voxels(N, grid, hits, threads, [&](VoxelCounts& counts, std::size_t begin, std::size_t end) {
        double q[kFkBlock * kMaxJoints];
        std::size_t i = begin;
        for (; i + kFkBlock <= end; i += kFkBlock) {
            for (int b = 0; b < kFkBlock; ++b) uniform_configuration(seed, first + i + b, n, low, high, q + n * b);
            counts.add_block(chain, grid, q);
        }
        for (; i < end; ++i) {
            uniform_configuration(seed, first + i, n, low, high, q);
            counts.add_one(chain, grid, q);
        }
    });
}

// Adds to hits the tool positions of the N configurations q (N x n, finite); returns the
// samples outside the grid.
inline std::int64_t count_given(const Chain& chain, const double* q, std::size_t N, const VoxelGrid& grid,
                                std::int64_t* hits, int threads) {
    const std::size_t n = std::size_t(chain.n);
    return count_voxels(N, grid, hits, threads, [&](VoxelCounts& counts, std::size_t begin, std::size_t end) {
        std::size_t i = begin;
        for (; i + kFkBlock <= end; i += kFkBlock) counts.add_block(chain, grid, q + n * i);
        for (; i < end; ++i) counts.add_one(chain, grid, q + n * i);
    });
}

// Fills q (N x n) with configurations [first, first + N) of the batch seeded `seed`, uniform in
// [low, high): the samples count_uniform draws.
inline void sample_uniform(int n, const double* low, const double* high, std::uint64_t seed, std::uint64_t first,
                           std::size_t N, double* q, int threads) {
    parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) uniform_configuration(seed, first + i, n, low, high, q + n * i);
    });
}

}  // namespace armkit
