// Reachability counting in one pass: configurations drawn uniformly inside a joint box (or
// given), their tool positions, the voxel each falls in and the hits per voxel, with no
// per-configuration arrays (armkit/workspace/reachability.py is the Python side).
//
// Random stream: configuration i of a batch seeded `seed` draws its n joint values from
// splitmix64 started at item_seed(seed, i) (a counter-based generator: each configuration's
// values depend on (seed, i) alone), so the samples, and the counts, are the same whatever
// the thread split.
//
// Speed: configurations go in blocks of kReachBlock, structure-of-arrays, through the
// vectorised sines and cosines and a position-only FK; voxels come from a product with the
// reciprocal resolution; each thread counts into its own array. The loops are built for
// AVX2 as well (reach.cpp). A position within rounding of a voxel face is recomputed the plain
// way, so the counts are exactly those of tool_pose's positions in VoxelGrid::flat_index.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "armkit/batch.hpp"
#include "armkit/fk.hpp"
#include "armkit/linalg.hpp"
#include "armkit/random.hpp"
#include "armkit/simd.hpp"

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

// The 53-bit words configuration `index` of the batch seeded `seed` draws, one per joint,
// from splitmix64 started at item_seed(seed, index); joint j's goes to bits[j * stride].
inline void configuration_bits(std::uint64_t seed, std::uint64_t index, int n, std::uint64_t* bits,
                               int stride = 1) {
    std::uint64_t state = item_seed(seed, index);
    for (int j = 0; j < n; ++j) bits[j * stride] = splitmix64(state) >> 11;
}

// double(bits) for bits < 2^53, in operations the compiler vectorises: the two halves through
// the 2^52 exponent, each exact, and their exact sum.
inline double exact_double(std::uint64_t bits) {
    constexpr std::uint64_t kExponent52 = 0x4330000000000000ull;
    const std::uint64_t high = (bits >> 26) | kExponent52, low = (bits & 0x3FFFFFFull) | kExponent52;
    double h, l;
    std::memcpy(&h, &high, sizeof h);
    std::memcpy(&l, &low, sizeof l);
    return (h - 0x1.0p52) * 0x1.0p26 + (l - 0x1.0p52);
}

// A joint value uniform in [low, high) from a 53-bit word: the word scaled, as Random::uniform.
inline double uniform_value(double low, double high, std::uint64_t bits) {
    return low + (high - low) * (exact_double(bits) * 0x1.0p-53);
}

//: Configurations a counting step handles together, structure-of-arrays (joint j of
//: configuration b at q[j * kReachBlock + b]): long enough for the vectorised sines and cosines
//: and loops the compiler vectorises, short enough for the block to stay in L1.
constexpr int kReachBlock = 64;

// Tool positions (x, y, z) of the kReachBlock configurations of a block, position only:
// p = B_0 Z_1(q_1) B_1 ... Z_n(q_n) B_n o from the right, a vector through each transform
// (about 25 operations a joint, a third of the pose product's). The sines and cosines are
// sin_cos's, as every FK path's; p differs from tool_pose's position by rounding only.
// (Always inlined: reach.cpp's AVX2 build of the loops then computes it with AVX2 too.)
ARMKIT_INLINE void tool_positions_block(const Chain& chain, const double* q, double* x, double* y, double* z) {
    constexpr int B = kReachBlock;
    double s[B], c[B];
    const Pose& tool = chain.between[std::size_t(chain.n)];
    for (int b = 0; b < B; ++b) {
        x[b] = tool(0, 3);
        y[b] = tool(1, 3);
        z[b] = tool(2, 3);
    }
    for (int j = chain.n - 1; j >= 0; --j) {
        const double* qj = q + j * B;
        if (chain.prismatic[std::size_t(j)]) {
            for (int b = 0; b < B; ++b) z[b] += qj[b];
        } else {
            sin_cos(qj, s, c, B);
            for (int b = 0; b < B; ++b) {
                const double u = x[b], v = y[b];
                x[b] = c[b] * u - s[b] * v;
                y[b] = s[b] * u + c[b] * v;
            }
        }
        const Pose& L = chain.between[std::size_t(j)];
        for (int b = 0; b < B; ++b) {
            const double u = x[b], v = y[b], w = z[b];
            x[b] = L(0, 0) * u + L(0, 1) * v + L(0, 2) * w + L(0, 3);
            y[b] = L(1, 0) * u + L(1, 1) * v + L(1, 2) * w + L(1, 3);
            z[b] = L(2, 0) * u + L(2, 1) * v + L(2, 2) * w + L(2, 3);
        }
    }
}

// The voxel of a position computed the fast way (tool_positions_block, times the reciprocal of
// the resolution), and when it lies so near a voxel face that rounding could decide it, the
// position of tool_pose in VoxelGrid::flat_index (division): so the counts are exactly those
// of tool_pose's positions put in the grid, at the fast path's cost everywhere else.
struct FastVoxels {
    const VoxelGrid& grid;
    double inverse;         // 1 / resolution
    double fixed_length;    // sum of the chain's fixed translations [m]
    double rounding;        // relative rounding bound of a position and of (p - lower) * inverse
    double far_from_origin; // largest |lower| + extent of the grid [m]

    //: Rounding steps a position or voxel coordinate may be off by, per joint and then some: the
    //: two FK orders differ by at most a few steps per joint (sines and cosines are shared), and
    //: the product by the reciprocal by at most two steps from the quotient.
    static constexpr double kSteps = 64.0;

    FastVoxels(const Chain& chain, const VoxelGrid& g) : grid(g), inverse(1.0 / g.resolution) {
        fixed_length = 0.0;
        for (const Pose& L : chain.between) fixed_length += norm(L.position());
        rounding = kSteps * double(chain.n + 2) * 0x1.0p-52;
        far_from_origin = 0.0;
        for (int a = 0; a < 3; ++a)
            far_from_origin = std::max(far_from_origin, std::abs(g.lower[a]) + double(g.shape[a]) * g.resolution);
    }

    // The margin [voxels] within which a voxel face is too close to call, for positions no
    // longer than `length` [m] (the fixed translations plus the prismatic travel).
    double margin(double length) const { return rounding * (length + far_from_origin) * inverse + rounding; }
};

// Hits per voxel and samples outside the grid of one thread's share of a batch.
struct VoxelCounts {
    std::int64_t* hits;  // grid.size() counters
    std::int64_t outside = 0;

    void add(std::int64_t flat) {
        if (flat < 0)
            ++outside;
        else
            ++hits[flat];
    }

    // Counts the tool positions of the first m configurations of a block q (joint j of
    // configuration b at q[j * kReachBlock + b]; the block's other entries finite). Always
    // inlined, as tool_positions_block.
    ARMKIT_INLINE void add_block(const Chain& chain, const FastVoxels& fast, const double* q, int m) {
        constexpr int B = kReachBlock;
        const int n = chain.n;
        double length = fast.fixed_length;
        for (int j = 0; j < n; ++j)
            if (chain.prismatic[std::size_t(j)]) {
                double travel = 0.0;
                for (int b = 0; b < m; ++b) travel = std::max(travel, std::abs(q[j * B + b]));
                length += travel;
            }
        const double margin = fast.margin(length);
        double p[3][B];
        tool_positions_block(chain, q, p[0], p[1], p[2]);
        std::int64_t flat[B];
        bool near[B];
        for (int b = 0; b < B; ++b) {
            flat[b] = 0;
            near[b] = false;
        }
        bool inside[B];
        for (int b = 0; b < B; ++b) inside[b] = true;
        for (int a = 0; a < 3; ++a) {
            const double lower = fast.grid.lower[a], extent = double(fast.grid.shape[a]);
            const std::int64_t stride = fast.grid.shape[a];
            for (int b = 0; b < B; ++b) {
                const double u = (p[a][b] - lower) * fast.inverse;
                const double cell = std::floor(u);
                near[b] |= (u - cell < margin) | (cell + 1.0 - u < margin);
                inside[b] &= (cell >= 0.0) & (cell < extent);
                flat[b] = flat[b] * stride + std::int64_t(inside[b] ? cell : 0.0);
            }
        }
        for (int b = 0; b < m; ++b) {
            if (near[b]) {
                double row[kMaxJoints];
                for (int j = 0; j < n; ++j) row[j] = q[j * B + b];
                const Pose T = tool_pose(chain, row);
                add(fast.grid.flat_index(T(0, 3), T(1, 3), T(2, 3)));
            } else {
                add(inside[b] ? flat[b] : -1);
            }
        }
    }
};

// Runs fill(counts, begin, end) on pieces of items [0, N) in up to `threads` threads (as
// parallel_pieces), each thread counting into its own array (the first thread straight into
// hits); the others' arrays are then added into hits (grid.size()), integer sums whose order
// does not matter. Returns the samples outside the grid.
template <class Fill>
std::int64_t count_voxels(std::size_t N, const VoxelGrid& grid, std::int64_t* hits, int threads, Fill&& fill) {
    const std::size_t T = batch_threads(N, threads);
    std::vector<std::vector<std::int64_t>> own(T - 1);  // the other threads' counts
    std::vector<VoxelCounts> counts;
    counts.reserve(T);
    counts.push_back(VoxelCounts{hits});
    for (auto& array : own) {
        array.assign(std::size_t(grid.size()), 0);
        counts.push_back(VoxelCounts{array.data()});
    }
    parallel_pieces(N, threads, [&](std::size_t worker, std::size_t begin, std::size_t end) {
        fill(counts[worker], begin, end);
    });
    std::int64_t outside = 0;
    for (const VoxelCounts& c : counts) outside += c.outside;
    for (const auto& array : own)
        for (std::size_t v = 0; v < array.size(); ++v) hits[v] += array[v];
    return outside;
}

// Counts configurations [first + begin, first + end) of the batch seeded `seed`, uniform in
// [low, high), into counts (reach.cpp: built for AVX2 too, chosen at run time).
void count_uniform_piece(const Chain& chain, const FastVoxels& fast, const double* low, const double* high,
                         std::uint64_t seed, std::uint64_t first, std::size_t begin, std::size_t end,
                         VoxelCounts& counts);

// Counts configurations [begin, end) of q (N x n, finite) into counts (reach.cpp).
void count_given_piece(const Chain& chain, const FastVoxels& fast, const double* q, std::size_t begin,
                       std::size_t end, VoxelCounts& counts);

// Adds to hits the tool positions of configurations [first, first + N) of the batch seeded
// `seed`, uniform in the box [low, high) (n values each); returns the samples outside the grid.
inline std::int64_t count_uniform(const Chain& chain, const double* low, const double* high, std::uint64_t seed,
                                  std::uint64_t first, std::size_t N, const VoxelGrid& grid, std::int64_t* hits,
                                  int threads) {
    const FastVoxels fast(chain, grid);
    return count_voxels(N, grid, hits, threads, [&](VoxelCounts& counts, std::size_t begin, std::size_t end) {
        count_uniform_piece(chain, fast, low, high, seed, first, begin, end, counts);
    });
}

// Adds to hits the tool positions of the N configurations q (N x n, finite); returns the
// samples outside the grid.
inline std::int64_t count_given(const Chain& chain, const double* q, std::size_t N, const VoxelGrid& grid,
                                std::int64_t* hits, int threads) {
    const FastVoxels fast(chain, grid);
    return count_voxels(N, grid, hits, threads, [&](VoxelCounts& counts, std::size_t begin, std::size_t end) {
        count_given_piece(chain, fast, q, begin, end, counts);
    });
}

// Fills q (N x n) with configurations [first, first + N) of the batch seeded `seed`, uniform in
// [low, high): the samples count_uniform draws.
inline void sample_uniform(int n, const double* low, const double* high, std::uint64_t seed, std::uint64_t first,
                           std::size_t N, double* q, int threads) {
    parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
        std::uint64_t bits[kMaxJoints];
        for (std::size_t i = begin; i < end; ++i) {
            configuration_bits(seed, first + i, n, bits);
            double* qi = q + std::size_t(n) * i;
            for (int j = 0; j < n; ++j) qi[j] = uniform_value(low[j], high[j], bits[j]);
        }
    });
}

}  // namespace armkit
