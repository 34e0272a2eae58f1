// sin_cos: dispatch between libmvec's AVX2 variants (sin_cos_avx2.cpp, the only file built
// with -mavx2) and the scalar library, decided once from the CPU.
#include "armkit/sin_cos.hpp"

#include <cmath>

namespace armkit {

#if defined(ARMKIT_LIBMVEC)
void sin_cos_avx2(const double* x, double* s, double* c, int count);  // sin_cos_avx2.cpp

bool vectorised_sin_cos() {
    static const bool avx2 = __builtin_cpu_supports("avx2");
    return avx2;
}
#else
bool vectorised_sin_cos() { return false; }
#endif

void sin_cos(const double* x, double* s, double* c, int count) {
#if defined(ARMKIT_LIBMVEC)
    if (vectorised_sin_cos()) return sin_cos_avx2(x, s, c, count);
#endif
    for (int k = 0; k < count; ++k) {
        s[k] = std::sin(x[k]);
        c[k] = std::cos(x[k]);
    }
}

}  // namespace armkit
