// Sine and cosine of many angles at once, for the batch kernels (FK blocks, reach maps).
#pragma once

namespace armkit {

// s[k] = sin(x[k]), c[k] = cos(x[k]) for k < count. With glibc's vectorised math library
// (libmvec, AVX2: four angles per instruction, within 4 ulp of the exact values) where the
// build found it and the CPU has AVX2; otherwise std::sin and std::cos (within 1 ulp).
void sin_cos(const double* x, double* s, double* c, int count);

// Whether sin_cos runs libmvec's AVX2 variants on this machine.
bool vectorised_sin_cos();

}  // namespace armkit
