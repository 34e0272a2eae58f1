// SCARA and planar 2R/3R arms (ik_case_planar.hpp): angle sum, height along the axes, planar 2R.
#include "armkit/ik_case_planar.hpp"

#include "armkit/subproblems.hpp"

namespace armkit {

// SCARA / planar arm: angle sum, height, planar 2R: 2 candidates.
void solve_case(const PlanarGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    const Vec3 h = g.hp, y = g.y;
    const int* rev = g.revolute;
    const int n = g.n;
    const double theta = sp1(g.u, R * g.u, h).t;
    const Vec3 Gy = R * y + t;
    const double slide = g.prismatic_joint >= 0 ? dot(Gy - y, h) : 0.0;
    const Vec3 p_a = g.p[rev[0]], p_b = g.p[rev[1]];
    const Planar2 ab = planar_2r(h, p_b - p_a, y - p_b, (Gy - slide * h) - p_a);
    for (int b = 0; b < 2; ++b) {
        double* qs = q + n * b;
        for (int j = 0; j < n; ++j) qs[j] = 0.0;
        qs[rev[0]] = ab.ta[b];
        qs[rev[1]] = ab.tb[b];
        if (g.revolute_count == 3) qs[rev[2]] = theta - ab.ta[b] - ab.tb[b];
        if (g.prismatic_joint >= 0) qs[g.prismatic_joint] = slide;
        valid[b] = ab.ok[b];
        family[b] = ab.free;
    }
}

}  // namespace armkit
