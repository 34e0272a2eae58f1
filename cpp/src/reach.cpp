// The reachability kernel's loops (reach.hpp), built for the baseline CPU and for AVX2
// (armkit/simd.hpp).
#include "armkit/reach.hpp"

#include "armkit/simd.hpp"

namespace armkit {

ARMKIT_AVX2_CLONES
void count_uniform_piece(const Chain& chain, const FastVoxels& fast, const double* low, const double* high,
                         std::uint64_t seed, std::uint64_t first, std::size_t begin, std::size_t end,
                         VoxelCounts& counts) {
    const int n = chain.n;
    double q[kMaxJoints * kReachBlock] = {};
    std::uint64_t bits[kMaxJoints * kReachBlock] = {};
    for (std::size_t i = begin; i < end; i += kReachBlock) {
        const int m = int(std::min<std::size_t>(kReachBlock, end - i));
        for (int b = 0; b < m; ++b) configuration_bits(seed, first + i + b, n, bits + b, kReachBlock);
        for (int j = 0; j < n; ++j)
            for (int b = 0; b < kReachBlock; ++b)
                q[j * kReachBlock + b] = uniform_value(low[j], high[j], bits[j * kReachBlock + b]);
        counts.add_block(chain, fast, q, m);
    }
}

ARMKIT_AVX2_CLONES
void count_given_piece(const Chain& chain, const FastVoxels& fast, const double* q, std::size_t begin,
                       std::size_t end, VoxelCounts& counts) {
    const int n = chain.n;
    double block[kMaxJoints * kReachBlock] = {};
    for (std::size_t i = begin; i < end; i += kReachBlock) {
        const int m = int(std::min<std::size_t>(kReachBlock, end - i));
        for (int b = 0; b < m; ++b)
            for (int j = 0; j < n; ++j) block[j * kReachBlock + b] = q[std::size_t(n) * (i + b) + std::size_t(j)];
        for (int b = m; b < kReachBlock; ++b)
            for (int j = 0; j < n; ++j) block[j * kReachBlock + b] = 0.0;
        counts.add_block(chain, fast, block, m);
    }
}

}  // namespace armkit
