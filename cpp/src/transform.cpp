#include "armkit/transform.hpp"

#include <algorithm>

namespace armkit {

Rigidity rigidity(const double* T, std::size_t N) {
    Rigidity out;
    for (std::size_t i = 0; i < N; ++i) {
        const double* M = T + 16 * i;
        for (int k = 0; k < 16; ++k)
            if (!std::isfinite(M[k])) return Rigidity{false, 0.0, 0.0, 0};
        out.last_row = std::max({out.last_row, std::fabs(M[12]), std::fabs(M[13]), std::fabs(M[14]),
                                 std::fabs(M[15] - 1.0)});
        double worst = 0.0;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                const double d = M[a] * M[b] + M[4 + a] * M[4 + b] + M[8 + a] * M[8 + b];
                worst = std::max(worst, std::fabs(d - (a == b ? 1.0 : 0.0)));
            }
        const double det = M[0] * (M[5] * M[10] - M[6] * M[9]) - M[1] * (M[4] * M[10] - M[6] * M[8]) +
                           M[2] * (M[4] * M[9] - M[5] * M[8]);
        out.rough += worst > 1e-14;
        out.orthonormal = std::max({out.orthonormal, worst, std::fabs(det - 1.0)});
    }
    return out;
}

}  // namespace armkit
