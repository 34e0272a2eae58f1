// A small deterministic random generator for the solvers' restart seeds: xoshiro256**
// (Blackman and Vigna, "Scrambled linear pseudorandom number generators", 2021) seeded
// through splitmix64, so one 64-bit seed gives one reproducible stream on every platform.
#pragma once

#include <cstdint>

namespace armkit {

// splitmix64: advances state and returns the next 64 well-mixed bits.
inline std::uint64_t splitmix64(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// The seed of item `index` of a batch whose base seed is `seed`: distinct for distinct
// indices (splitmix64 is a bijection), so each item has its own stream whatever thread runs it.
inline std::uint64_t item_seed(std::uint64_t seed, std::uint64_t index) {
    std::uint64_t mixed = splitmix64(seed) ^ index;
    return splitmix64(mixed);
}

class Random {
public:
    explicit Random(std::uint64_t seed) {
        for (auto& word : s_) word = splitmix64(seed);
    }

    // The next 64 bits (xoshiro256**).
    std::uint64_t next() {
        const std::uint64_t result = rotl(s_[1] * 5, 7) * 9, t = s_[1] << 17;
        s_[2] ^= s_[0];
        s_[3] ^= s_[1];
        s_[1] ^= s_[2];
        s_[0] ^= s_[3];
        s_[2] ^= t;
        s_[3] = rotl(s_[3], 45);
        return result;
    }

    // Uniform in [low, high): 53 random bits scaled, as NumPy's Generator.uniform does.
    double uniform(double low, double high) { return low + (high - low) * (double(next() >> 11) * 0x1.0p-53); }

private:
    static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    std::uint64_t s_[4];
};

}  // namespace armkit
