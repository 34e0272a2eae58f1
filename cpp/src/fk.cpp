#include "armkit/fk.hpp"

namespace armkit {

ARMKIT_AVX2_CLONES
void tool_poses_blocks(const Chain& chain, const double* q, double* out, std::size_t blocks) {
    const std::size_t n = std::size_t(chain.n);
    for (std::size_t k = 0; k < blocks; ++k) tool_poses_block(chain, q + k * kFkBlock * n, out + k * kFkBlock * 16);
}

void pose_error(const Pose& target, const Pose& T, double* e) {
    double X[3][3];  // R_target R^T
    for (int a = 0; a < 3; ++a) {
        e[a] = target(a, 3) - T(a, 3);
        for (int b = 0; b < 3; ++b)
            X[a][b] = target(a, 0) * T(b, 0) + target(a, 1) * T(b, 1) + target(a, 2) * T(b, 2);
    }
    const Vec3 v{X[2][1] - X[1][2], X[0][2] - X[2][0], X[1][0] - X[0][1]};  // 2 sin(angle) axis
    const double length = norm(v);
    const double trace = X[0][0] + X[1][1] + X[2][2];
    const double angle = std::atan2(length, trace - 1.0);
    if (trace <= 0.0) {
        // (R + R^T) / 2 - cos(angle) I = (1 - cos(angle)) axis axis^T: its column with the
        // largest diagonal entry is the axis times a factor; the sign is that of v.
        const double cosine = (trace - 1.0) / 2.0;
        int k = 0;
        for (int j = 1; j < 3; ++j)
            if (X[j][j] > X[k][k]) k = j;
        Vec3 axis{0.5 * (X[0][k] + X[k][0]) - (k == 0 ? cosine : 0.0),
                  0.5 * (X[1][k] + X[k][1]) - (k == 1 ? cosine : 0.0),
                  0.5 * (X[2][k] + X[k][2]) - (k == 2 ? cosine : 0.0)};
        double scale = angle / norm(axis);
        if (dot(axis, v) < 0.0) scale = -scale;
        e[3] = scale * axis.x;
        e[4] = scale * axis.y;
        e[5] = scale * axis.z;
        return;
    }
    const double scale = length > 1e-300 ? angle / length : 0.5;  // angle / (2 sin angle) -> 1/2
    e[3] = scale * v.x;
    e[4] = scale * v.y;
    e[5] = scale * v.z;
}

void pose_residual(const Pose& target, const Pose& F, double& position, double& angle) {
    position = norm(F.position() - target.position());
    double trace = 0.0;  // of X - I with X = R_target^T R, and the vector of its skew part
    Vec3 v;
    for (int c = 0; c < 3; ++c) {
        const double D0 = F(c, 0) - target(c, 0), D1 = F(c, 1) - target(c, 1), D2 = F(c, 2) - target(c, 2);
        const double R0 = target(c, 0), R1 = target(c, 1), R2 = target(c, 2);
        trace += R0 * D0 + R1 * D1 + R2 * D2;
        v.x += R2 * D1 - R1 * D2;
        v.y += R0 * D2 - R2 * D0;
        v.z += R1 * D0 - R0 * D1;
    }
    angle = std::atan2(norm(v), 2.0 + trace);
}

}  // namespace armkit
