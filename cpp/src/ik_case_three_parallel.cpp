// Three parallel axes 2-4 (ik_case_three_parallel.hpp): two equations in q1, q5 alone (a
// two-angle system), then q6 (SP1), q2 + q3 + q4 (SP1) and a planar 2R.
#include "armkit/ik_case_three_parallel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "armkit/subproblems.hpp"
#include "armkit/two_angle.hpp"

namespace armkit {

namespace {

// The index of the aligned value of q5 nearest t5, and t5's signed distance from it.
int nearest_aligned(const ThreeParallelGeometry& g, double t5, double& gap) {
    int nearest = 0;
    gap = std::numeric_limits<double>::infinity();
    for (int a = 0; a < g.aligned; ++a) {
        const double d = wrap_angle(t5 - g.q5_aligned[a]);
        if (std::abs(d) < std::abs(gap)) nearest = a, gap = d;
    }
    return nearest;
}

// 1 - |cos| of the angle between axis 6 and h for q1, from its sine (S = |h6 x R_G^T R1 h|):
// b (1 - cos d) at a distance d of q5 from the aligned value, S^2 / (1 + sqrt(1 - S^2)).
double misalignment(const ThreeParallelGeometry& g, const Mat3& R, double q1) {
    const Vec3 c = cross(g.h[5], mul_transposed(R, rotate(g.h[0], q1, g.hp)));
    const double S2 = std::min(dot(c, c), 1.0);
    return S2 / (1.0 + std::sqrt(1.0 - S2));
}

// Near an aligned wrist, q5 from a sine (accurate) rather than a cosine (~1e-8). h6 . R5^T h
// is the cosine-like quantity the equations give; at a distance d from the aligned value it
// differs from +-1 by b (1 - cos d) only, lost below d ~ 1e-8. S = |h6 x R_G^T R1 h| keeps
// its relative accuracy: b (1 - cos d) = S^2 / (1 + sqrt(1 - S^2)). The two branches of
// candidate pair s straddle the aligned value.
double q5_near_aligned_wrist(const ThreeParallelGeometry& g, const Mat3& R, double q1, double q5, int s) {
    if (g.aligned == 0) return q5;
    double gap;
    const int nearest = nearest_aligned(g, q5, gap);
    if (std::abs(gap) > kAlignedWristReach) return q5;
    const double one_minus_cos = misalignment(g, R, q1) / g.b_aligned;
    const double d = 2.0 * std::asin(std::min(std::sqrt(0.5 * one_minus_cos), 1.0));
    double sign;
    if (gap > 0)
        sign = 1.0;
    else if (gap < 0)
        sign = -1.0;
    else
        sign = s % 2 == 0 ? 1.0 : -1.0;  // (+d, -d) pairs
    return g.q5_aligned[nearest] + sign * d;
}

// Near an aligned wrist the system's first equation is at an extremum in both angles (axis 6
// cannot turn nearer to h than parallel), so its two roots there are a near-double pair of the
// quartic, each placed only to ~1e-8 in q1 and ~1e-7 in q5 (a UR5 with joint 6's point moved by
// 1e-2, at q5 = 1e-7: both roots polished onto one, or snapped, and the pose's own configuration
// lost). Each side of that equation is small there and is computed here from sines, to its own
// relative accuracy: E(q1) = (1 - |cos| of the angle between axis 6 and h for q1) - b (1 - cos d),
// d the distance from the aligned value a of the q5 the second equation gives for q1 (that
// equation is regular there: Q has rank 2). E's zeros are the pair's roots, simple ones.
struct AlignedGap {
    double E = 0.0, q5 = 0.0;
    bool ok = false;
};

AlignedGap aligned_gap(const ThreeParallelGeometry& g, const Mat3& R, const Mat2& P, const double* r, double size,
                       double a, double q1) {
    AlignedGap out;
    const double rhs = P.m[1][0] * std::cos(q1) + P.m[1][1] * std::sin(q1) - r[1];
    const Angles2 q5 = solve_trig_linear(g.Q[1][0], g.Q[1][1], rhs, size, false);
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 2; ++k) {
        const double d = wrap_angle(q5.t[k] - a);
        if (q5.ok[k] && std::abs(d) < std::abs(best)) best = d, out.q5 = q5.t[k];
    }
    if (!std::isfinite(best)) return out;
    const double half = std::sin(0.5 * best);
    out.E = misalignment(g, R, q1) - 2.0 * g.b_aligned * half * half;
    out.ok = true;
    return out;
}

// The quartic's roots within kAlignedWristReach of an aligned wrist (not rank 1), one or two
// within kAlignedPair of each other in q1 (a near-double pair, or one whose partner the quartic
// lost), replaced by the zeros of E beside them: E fitted by a quadratic in q1 on three points
// spanning them, its real zeros within those points taken by Newton steps on E itself and given
// to the roots in order (a second zero to a free slot where there is one root). Where the zeros
// are not there, the roots are left as they were (FK decides).
void split_near_aligned_pairs(const ThreeParallelGeometry& g, const Mat3& R, const Mat2& P, const double* r,
                              AngleCandidates& pair) {
    if (g.aligned == 0) return;
    const double size = system_size(P, r);
    bool done[4] = {};
    for (int i = 0; i < 4; ++i) {
        double gap;
        const int a = nearest_aligned(g, pair.t2[i], gap);
        if (done[i] || pair.free[i] || std::abs(gap) > kAlignedWristReach) continue;
        int group[4], members = 0;
        for (int j = i; j < 4; ++j) {
            double gap_j;
            if (!done[j] && !pair.free[j] && nearest_aligned(g, pair.t2[j], gap_j) == a &&
                std::abs(gap_j) <= kAlignedWristReach && std::abs(wrap_angle(pair.t1[j] - pair.t1[i])) <= kAlignedPair)
                group[members++] = j, done[j] = true;
        }
        if (members > 2) continue;  // three roots so near one another: no pair to split
        if (members == 2 && wrap_angle(pair.t1[group[1]] - pair.t1[group[0]]) < 0.0) std::swap(group[0], group[1]);
        const double half = members == 2 ? 0.5 * wrap_angle(pair.t1[group[1]] - pair.t1[group[0]]) : 0.0;
        const double centre = pair.t1[group[0]] + half, w = std::max(4.0 * half, kAlignedPairWidth);
        const double qa = g.q5_aligned[a];
        const AlignedGap lo = aligned_gap(g, R, P, r, size, qa, centre - w), mid = aligned_gap(g, R, P, r, size, qa, centre),
                         hi = aligned_gap(g, R, P, r, size, qa, centre + w);
        if (!(lo.ok && mid.ok && hi.ok)) continue;
        const double A = (hi.E + lo.E - 2.0 * mid.E) / (2.0 * w * w), B = (hi.E - lo.E) / (2.0 * w), C = mid.E;
        const double disc = B * B - 4.0 * A * C;
        if (!(A != 0.0)) continue;
        if (disc < 0.0) {  // no real zero: a pair goes to the vertex (between them, as near as any real
            // point), where the snap or FK decides; a single root is left as it was
            const AlignedGap vertex = aligned_gap(g, R, P, r, size, qa, centre - B / (2.0 * A));
            if (members == 2 && vertex.ok && std::abs(B / (2.0 * A)) <= w)
                for (int m = 0; m < 2; ++m) pair.t1[group[m]] = centre - B / (2.0 * A), pair.t2[group[m]] = vertex.q5;
            continue;
        }
        // the zeros of A u^2 + B u + C, the larger in size first (no cancellation), then Newton on E
        const double big = -0.5 * (B + std::copysign(std::sqrt(disc), B));
        double u[2] = {big / A, big != 0.0 ? C / big : 0.0};
        AlignedGap at[2];
        bool inside[2];
        for (int z = 0; z < 2; ++z) {
            for (int step = 0; step < 3; ++step) {
                at[z] = aligned_gap(g, R, P, r, size, qa, centre + u[z]);
                const double slope = 2.0 * A * u[z] + B;
                if (!at[z].ok || !(std::abs(slope) > 0.0) || !(std::abs(at[z].E / slope) <= w)) break;
                u[z] -= at[z].E / slope;
            }
            at[z] = aligned_gap(g, R, P, r, size, qa, centre + u[z]);
            inside[z] = at[z].ok && std::abs(u[z]) <= w;
        }
        if (u[0] > u[1]) std::swap(u[0], u[1]), std::swap(at[0], at[1]), std::swap(inside[0], inside[1]);
        if (members == 2 && !(inside[0] && inside[1])) continue;
        if (members == 1) {  // the zero nearer the root is its own; the other, if there, a free slot's
            if (std::abs(u[1]) < std::abs(u[0])) std::swap(u[0], u[1]), std::swap(at[0], at[1]), std::swap(inside[0], inside[1]);
            if (!inside[0]) continue;
            for (int j = 0; j < 4 && members == 1 && inside[1]; ++j)
                if (!pair.valid[j] && !done[j]) group[members++] = j, done[j] = true;
        }
        for (int m = 0; m < members; ++m) {
            pair.t1[group[m]] = centre + u[m];
            pair.t2[group[m]] = at[m].q5;
            pair.valid[group[m]] = true;
        }
    }
}

// Put q5 exactly where axis 6 is parallel to h when a quartic root is that close to it.
// There the quartic has a double root, which Newton steps reach only to ~1e-8; the exact
// value lets the family (q6 against q2 + q3 + q4) be recognised. q1 is then solved from
// P x1 = r + Q x5 (a 2x2 linear system).
void snap_to_aligned_wrist(const ThreeParallelGeometry& g, const Mat2& P, const double* r, double* t1, double* t5) {
    const double det = P.m[0][0] * P.m[1][1] - P.m[0][1] * P.m[1][0];
    const double size = 1.0 + std::max(std::max(std::abs(P.m[0][0]), std::abs(P.m[0][1])),
                                       std::max(std::abs(P.m[1][0]), std::abs(P.m[1][1])));
    if (g.aligned == 0 || std::abs(det) <= kAlignedWristSolvable * size) return;
    const auto& Q = g.Q;
    for (int i = 0; i < 4; ++i) {
        double gap;
        const int nearest = nearest_aligned(g, t5[i], gap);
        if (std::abs(gap) > kAlignedWristSnap) continue;
        const double q5 = g.q5_aligned[nearest];
        const double rhs0 = r[0] + Q[0][0] * std::cos(q5) + Q[0][1] * std::sin(q5);
        const double rhs1 = r[1] + Q[1][0] * std::cos(q5) + Q[1][1] * std::sin(q5);
        t1[i] = std::atan2((P.m[0][0] * rhs1 - P.m[1][0] * rhs0) / det, (P.m[1][1] * rhs0 - P.m[0][1] * rhs1) / det);
        t5[i] = q5;
    }
}

}  // namespace

// Axes 2-4 parallel: (q1, q5), then q6, q2 + q3 + q4 and a planar 2R: 8 candidates.
void solve_case(const ThreeParallelGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    const Vec3 h = g.hp, h0 = g.h[0], h4 = g.h[4], h5 = g.h[5];
    const Vec3 p0 = g.p[0], p1 = g.p[1], p2 = g.p[2], p3 = g.p[3];
    const Vec3 p5 = g.p5, p6 = g.p6;
    const int n = g.n;
    const Vec3 G_p6 = R * p6 + t;
    const TrigCoeffs e1 = trig_coeffs(h, -h0, R * h5);
    const TrigCoeffs e2 = trig_coeffs(h, -h0, G_p6 - p0);
    const Mat2 P{{{e1.cos_coeff, e1.sin_coeff}, {e2.cos_coeff, e2.sin_coeff}}};  // P x1 - Q x5 = r
    const double r[2] = {g.f[0] - e1.constant, g.f[1] - e2.constant};
    AngleCandidates pair = two_angle_system(g, P, r);
    if (g.rank1) {
        for (int i = 0; i < 4; ++i) pair.t2[i] = q5_near_aligned_wrist(g, R, pair.t1[i], pair.t2[i], i);
    } else {
        split_near_aligned_pairs(g, R, P, r, pair);
        snap_to_aligned_wrist(g, P, r, pair.t1, pair.t2);
    }
    // axis 6 within kAlignedToRounding of h at q5
    auto axis6_parallel_to_rounding = [&](double q5) { return norm(cross(rotate(-h4, q5, h), h5)) <= kAlignedToRounding; };
    // q6, q2 + q3 + q4 and the planar 2R's target for (q1, q5)
    // (nearly_free: q6 within kAlignedToRounding of free counts as free)
    auto arm = [&](double q5, double q1, Angle1& q6, double& theta, double side, bool nearly_free) {
        // q6: R6^T (R5^T h) = R_G^T R1 h
        const Vec3 v = rotate(-h4, q5, h);
        q6 = sp1(v, mul_transposed(R, rotate(h0, q1, h)), -h5);
        q6.free = q6.free || (nearly_free && axis6_parallel_to_rounding(q5));
        // q2 + q3 + q4: R234 = R1^T R_G R6^T R5^T, applied to a normal of h
        const Vec3 turned = rotate(-h0, q1, R * rotate(-h5, q6.t, rotate(-h4, q5, g.u)));
        theta = sp1(g.u, turned, h).t;
        // planar part: e2 e3 e4 y = z with y = e5 p6, z = e1^-1 G p6
        const Vec3 y = p5 + rotate(h4, q5, p6 - p5);
        const Vec3 z = p0 + rotate(-h0, q1, G_p6 - p0);
        if (q6.free)  // axis 6 parallel to h: a family of q6, one loop of it per elbow slot
            wrist_family_representative(g, sign_of(dot(v, h5)), q6.t, theta, z - p1, y - p3, p2 - p1, p3 - p2, side);
        return (z - p1) - rotate(h, theta, y - p3);
    };
    const SlotAngles slots = family_slots(
        g, P, r, pair, [&](double q5, double q1, Angle1& q6, double& theta, double side) { return arm(q5, q1, q6, theta, side, false); },
        p2 - p1, p3 - p2);
    for (int i = 0; i < 4; ++i) {
        Angle1 q6;
        double theta;
        Planar2 q23{};
        for (int b = 0; b < 2; ++b) {
            const double q1 = slots.t1[i][b], q5 = slots.t2[i][b];
            const double side = b == 0 ? 1.0 : -1.0;
            if (b == 0 || q1 != slots.t1[i][0] || q5 != slots.t2[i][0] || q6.free)
                q23 = planar_2r(h, p2 - p1, p3 - p2, arm(q5, q1, q6, theta, side, false));
            // axis 6 within kAlignedToRounding of h, and the 2R cannot follow: q1 and q5 carry
            // the errors of a near-tangent root (seen 4e-12, leaving q6 0.008 off), so q6 is
            // taken as free (which misses the pose by about that angle times the arm's size),
            // the family's member refined by FK later
            if (!q23.ok[b] && !q6.free && axis6_parallel_to_rounding(q5)) {
                Angle1 free6;
                double free_theta;
                const Planar2 again = planar_2r(h, p2 - p1, p3 - p2, arm(q5, q1, free6, free_theta, side, true));
                if (free6.free && again.ok[b]) q23 = again, q6 = free6, theta = free_theta;
            }
            const int s = 2 * i + b;
            double* qs = q + n * s;
            qs[0] = q1;
            qs[1] = q23.ta[b];
            qs[2] = q23.tb[b];
            qs[3] = theta - q23.ta[b] - q23.tb[b];
            qs[4] = q5;
            qs[5] = q6.t;
            valid[s] = slots.valid[i][b] && q23.ok[b];
            family[s] = pair.free[i] || q6.free || q23.free;
        }
    }
}

// ------------------------------------------------------------------------ detection

namespace {

// Axes 2-4 of `arm` parallel to h: two equations in q1, q5; p5, p6 the closest points of
// axes 5 and 6, and the values of q5 that turn axis 6 parallel to h.
ThreeParallelGeometry three_parallel_geometry(const ArmLines& arm) {
    ThreeParallelGeometry g;
    static_cast<CaseChain&>(g) = arm;
    const Vec3* h = arm.h;
    const Vec3 hp = h[1];
    closest_points(arm.p[4], h[4], arm.p[5], h[5], g.p5, g.p6);
    // right-hand sides hp . R(h5, q5) v = const + c cos q5 + d sin q5, for v = h6, p6 - p5
    const TrigCoeffs a = trig_coeffs(hp, h[4], h[5]), b = trig_coeffs(hp, h[4], g.p6 - g.p5);
    const double Q[2][2] = {{a.cos_coeff, a.sin_coeff}, {b.cos_coeff, b.sin_coeff}};
    // q5 near an aligned wrist is refined from sines, so its cosine equation must not snap
    static_cast<TwoAngleSystem&>(g) = two_angle_constants(Q, a.constant, b.constant + dot(hp, g.p5 - arm.p[0]), false);
    g.hp = hp;
    g.u = unit_normal(hp);
    for (double side : {1.0, -1.0}) {
        const Angles2 s = sp4(hp, h[5], h[4], side);
        for (int i = 0; i < 2; ++i)
            if (s.ok[i] && g.aligned < 4) g.q5_aligned[g.aligned++] = s.t[i];
    }
    g.b_aligned = norm(cross(h[4], hp)) * norm(cross(h[4], h[5]));
    return g;
}

}  // namespace

bool three_parallel_block(const ArmLines& arm, int first) {
    if (!(parallel(arm, first, first + 1) && parallel(arm, first, first + 2))) return false;
    // the axes next to the block must leave it, and the ones after must not be parallel
    const int after = first + 3;
    return !(first == 1 && parallel(arm, 0, first)) && !parallel(arm, after, first) &&
           !parallel(arm, after, after + 1) && !parallel(arm, 4, 5);
}

Detection<ThreeParallelGeometry> detect_three_parallel(const ArmLines& arm) {
    CaseReason why;
    if (!six_revolute(arm, "the three-parallel case", why)) return why;
    for (const ArmLines& lines : {arm, reversed(arm)}) {
        if (!three_parallel_block(lines, 1)) continue;
        const ArmLines a = aligned(lines, {1, 2, 3}, lines.h[1]);
        // axes 5 and 6 within kNearSubcase of a sub-case (meeting: the two-angle system nearly
        // of rank 1; or axis 6 able to turn almost, not exactly, parallel to the block: the
        // wrist almost aligns), not to kClassTolerance: the quartic loses roots near an aligned
        // wrist (a UR5 with joint 5's point moved or joint 6's axis turned by 1e-8 .. 1e-6: 1-6
        // of 8 solutions listed at q5 = 1e-4 .. 1e-2, on 60 of 480 poses). Such an arm is near
        // the sub-case and is solved as arms near a class are: the general solver, seeded
        // (within kNearClass) by this case on the arm moved onto it (snap_to_class).
        double meeting, aligning;
        wrist_subcase_gaps(a, meeting, aligning);
        const auto near = [](double gap) { return gap > kClassTolerance && gap <= kNearSubcase; };
        if (near(meeting) || near(aligning))
            return CaseReason{CaseFit::Axes, "axes " + axes_text(a, {1, 2, 3}) + " are parallel, but axes " +
                                                 axes_text(a, {4, 5}) + (near(meeting) ? " nearly meet" : " nearly "
                                                 "let the wrist align") + " (within 1e-3, not to rounding): the general "
                                                 "solver, seeded by this case on the arm moved onto it within 1e-6"};
        ThreeParallelGeometry g = three_parallel_geometry(a);
        const bool polish = !g.rank1;
        const std::string axes = axes_text(a, {1, 2, 3});
        return CaseMatch<ThreeParallelGeometry>{
            g, a, "three-parallel", "three parallel axes: axes " + axes + " are parallel: closed-form IK, up to 8 solutions",
            polish};
    }
    return CaseReason{CaseFit::Axes, "neither axes 2, 3, 4 nor 3, 4, 5 are parallel (with the axes next to them not)"};
}

}  // namespace armkit
