// Batch loops built twice where the compiler can: for the baseline CPU and for AVX2, the
// loader choosing by the CPU (GCC's target_clones, an ifunc; x86-64 Linux). Without FMA
// (not asked for), the AVX2 build computes the same numbers, four lanes at a time. What such
// a loop calls must be inlined into it to run as AVX2 (ARMKIT_INLINE on the helpers).
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define ARMKIT_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define ARMKIT_AVX2_CLONES
#endif

#if defined(__GNUC__)
#define ARMKIT_INLINE [[gnu::always_inline]] inline
#else
#define ARMKIT_INLINE inline
#endif
