// libmvec's AVX2 sine and cosine (glibc >= 2.22, x86-64), four angles per call. This file alone
// is compiled with -mavx2; sin_cos.cpp calls it only on a CPU that has AVX2.
#include <immintrin.h>

// the vector ABI names of glibc's libmvec: 'd' = AVX2, 4 lanes, one vector argument
extern "C" __m256d _ZGVdN4v_sin(__m256d);
extern "C" __m256d _ZGVdN4v_cos(__m256d);

namespace armkit {

void sin_cos_avx2(const double* x, double* s, double* c, int count) {
    int k = 0;
    for (; k + 4 <= count; k += 4) {
        const __m256d v = _mm256_loadu_pd(x + k);
        _mm256_storeu_pd(s + k, _ZGVdN4v_sin(v));
        _mm256_storeu_pd(c + k, _ZGVdN4v_cos(v));
    }
    if (k == count) return;
    double lanes[4] = {0.0, 0.0, 0.0, 0.0}, sines[4], cosines[4];
    for (int i = k; i < count; ++i) lanes[i - k] = x[i];
    const __m256d v = _mm256_loadu_pd(lanes);
    _mm256_storeu_pd(sines, _ZGVdN4v_sin(v));
    _mm256_storeu_pd(cosines, _ZGVdN4v_cos(v));
    for (int i = k; i < count; ++i) {
        s[i] = sines[i - k];
        c[i] = cosines[i - k];
    }
}

}  // namespace armkit
