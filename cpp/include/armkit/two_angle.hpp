// The two-angle system of the closed-form cases: P x(t1) - Q x(t2) = r, x(t) = [cos t, sin t],
// with Q (2 x 2) fixed by the chain and P, r by the pose. Three parallel axes (in q1, q5 or
// q6, q4) and general axes 1-3 (in q1, q3) reduce to it. Q of rank 1: a combination of the
// equations holds t1 alone; otherwise a quartic in exp(i t1), then Newton steps on the
// equations themselves (two_angle.cpp). A family (every t1 a solution) is sampled for its
// loops (family_loops, family_slots: templates over the rest of the chain).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "armkit/subproblems.hpp"
#include "armkit/vec.hpp"

namespace armkit {

// The constant part of a two-angle system: Q, its inverse (zero when of rank 1), the
// constant f that r is measured from, and for Q of rank 1 the combinations lam (holds t1
// alone) and mu.
struct TwoAngleSystem {
    double Q[2][2] = {{0, 0}, {0, 0}};
    double Q_inv[2][2] = {{0, 0}, {0, 0}};
    double f[2] = {0, 0};
    bool rank1 = false;
    double lam[2] = {0, 0}, mu[2] = {0, 0};
    bool snap_t2 = true;  // snap t2 to a double root at tangency (off where t2 is refined from sines)
};

// The 2x2 matrix of a two-angle system P x(t1) - Q x(t2) = r, x(t) = [cos t, sin t].
struct Mat2 {
    double m[2][2];
};

// The four candidates of a two-angle system.
struct AngleCandidates {
    double t1[4], t2[4];
    bool valid[4], free[4];
};

inline double sign_of(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }

// t2 of the two-angle system for t1: x(t2) = Q^-1 (P x(t1) - r), its direction.
double second_angle(const TwoAngleSystem& g, const Mat2& P, const double* r, double t1);

// The size of the terms of P x(t1) - Q x(t2) = r that depend on the pose.
double system_size(const Mat2& P, const double* r);

// t2 for t1 of a candidate of the two-angle system whose t1 is free (branch: candidate
// index i, whose t2 branch is i % 2 when Q has rank 1); ok: that t2 exists.
double family_t2(const TwoAngleSystem& g, const Mat2& P, const double* r, double t1, int i, double size, bool& ok);

// All (t1, t2) with P x(t1) - Q x(t2) = r (Q = g.Q fixed by the chain; P, r by the pose).
// Q of rank 1: a combination of the equations holds t1 alone, then t2 the same way (up to
// 2 x 2 pairs). Otherwise x(t2) = Q^-1 (P x(t1) - r) on the unit circle is a quartic in
// exp(i t1) (then Newton steps on the equations themselves); where it vanishes, every t1
// (candidate 0, t1 = 0). free: t1 (or t2) arbitrary (family_t2 then gives t2 for any t1).
AngleCandidates two_angle_system(const TwoAngleSystem& g, const Mat2& P, const double* r);

// ---------------------------------------------------- families of the two-angle system

// A wrist axis parallel to the three parallel axes (axis 6 to axes 2-4, or axis 5 to axes
// 1-3): the member of the family that is best reachable. Along the family the angle sum
// theta of the three parallel joints changes against the wrist joint's angle qw (theta + s qw
// constant, s = +-1: the wrist axis along or against h), and the planar target A - R(h,
// theta) B turns on a circle; choose the angle that puts its length where the planar 2R
// of links a, b reaches best (|v|^2 = |a|^2 + |b|^2). |v|^2 is a sinusoid in theta, so the
// 2R reaches it on at most two intervals of theta, each a separate loop of the family: the
// two angles where it crosses that middle value (side = +1 or -1) lie one in each. Returns
// qw and theta.
template <class G>
void wrist_family_representative(const G& g, double s, double& qw, double& theta, Vec3 A, Vec3 B,
                                 Vec3 a, Vec3 b, double side) {
    const Vec3 h = g.hp;
    A = detail::in_plane(A, h);
    B = detail::in_plane(B, h);
    a = detail::in_plane(a, h);
    b = detail::in_plane(b, h);
    const double wanted = 0.5 * (dot(A, A) + dot(B, B) - dot(a, a) - dot(b, b));  // A . R(h, phi) B
    const double cos_part = dot(A, B), sin_part = dot(A, cross(h, B));
    const double r = std::sqrt(cos_part * cos_part + sin_part * sin_part);
    if (r == 0.0) return;
    const double phi = std::atan2(sin_part, cos_part) + side * std::acos(std::min(std::max(wanted / r, -1.0), 1.0));
    qw = qw + s * (theta - phi);
    theta = phi;
}

//: Members of a family of the two-angle system sampled round the circle for its loops.
constexpr int kFamilyMembers = 64;

//: Loops of one family given a member at most: its candidates' slots, 4 x 2 elbows where
//: the quartic vanishes, 2 x 2 for a t2 branch where Q has rank 1 (family_slots keeps the
//: best reached of any more).
constexpr int kMaxLoops = 8;

// A member (t1, t2) of a family of the two-angle system, and f there (see family_loops).
struct FamilyMember {
    double t1, t2, f;
};

// The least value of value(t, t2) on [lo, hi] (a bracket of one local minimum) by
// golden-section search, with its t2.
template <class Value>
FamilyMember golden_minimum(Value value, double lo, double hi) {
    constexpr double golden = 0.6180339887498949;
    constexpr int kGoldenSteps = 80;  // the bracket shrinks to rounding long before
    FamilyMember left{hi - golden * (hi - lo), 0.0, 0.0}, right{lo + golden * (hi - lo), 0.0, 0.0};
    left.f = value(left.t1, left.t2), right.f = value(right.t1, right.t2);
    FamilyMember best = left.f < right.f ? left : right;
    for (int k = 0; k < kGoldenSteps && hi - lo > 4.0 * std::numeric_limits<double>::epsilon() * (1.0 + std::abs(hi)); ++k) {
        if (left.f < right.f) {
            hi = right.t1, right = left;
            left.t1 = hi - golden * (hi - lo), left.f = value(left.t1, left.t2);
        } else {
            lo = left.t1, left = right;
            right.t1 = lo + golden * (hi - lo), right.f = value(right.t1, right.t2);
        }
        if (left.f < best.f) best = left;
        if (right.f < best.f) best = right;
    }
    return best;
}

//: Bisection steps for a crossing of the middle reach (the bracket then is at rounding).
constexpr int kBisectionSteps = 52;

// The point between members a and b (f of opposite signs) where f(t1) = 0, by bisection
// (stops where t1 has no t2); returns the end with the smaller |f|.
template <class Reach>
FamilyMember bisect_middle(Reach reach, FamilyMember a, FamilyMember b) {
    for (int k = 0; k < kBisectionSteps; ++k) {
        FamilyMember mid{0.5 * (a.t1 + b.t1), 0.0, 0.0};
        mid.f = reach(mid.t1, mid.t2);
        if (!std::isfinite(mid.f)) break;
        ((mid.f < 0.0) == (a.f < 0.0) ? a : b) = mid;
    }
    return std::abs(a.f) <= std::abs(b.f) ? a : b;
}

// Candidate i of pair has a free t1 (a family of the two-angle system): a member (t1, t2)
// on each loop of the family, the one whose planar target (target_of(t2, t1, ...), for the
// 2R of links a, b) the 2R reaches best, into loops (at most kMaxLoops, best first; their
// number returned). With f(t1) = (|v|^2 - (|a|^2 + |b|^2)) / (2 |a| |b|), the 2R reaches
// where |f| <= 1, best where f = 0, and each interval of t1 where it reaches is one loop
// (its two elbows meet at the ends). f is sampled at kFamilyMembers values of t1 round the
// circle, each sampled extremum refined by golden-section search (a loop narrower than the
// samples lies beside one, and a loop that touches the 2R's reach at one point is one), and
// the pieces between are taken as monotone: a loop's member is where f crosses 0 (bisection),
// else its point of least |f|. Every member solves the system exactly; which one stands for a
// loop only decides whether the rest of the chain can follow (the walk to near comes later).
template <class G, class Target>
int family_loops(const G& g, const Mat2& P, const double* r, int i, double start, Target target_of,
                 Vec3 a, Vec3 b, FamilyMember* loops) {
    const Vec3 h = g.hp;
    a = detail::in_plane(a, h);
    b = detail::in_plane(b, h);
    const double middle = dot(a, a) + dot(b, b), half_width = std::max(2.0 * std::sqrt(dot(a, a) * dot(b, b)), 1e-300);
    const double size = system_size(P, r);
    const double band = 1.0 + kFamilyReach * (1.0 + middle / half_width);  // |f| within: reached, to rounding
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    // f(t1), and t2; NaN where t1 has no t2
    auto reach = [&](double t1, double& t2) {
        bool ok;
        t2 = family_t2(g, P, r, t1, i, size, ok);
        if (!ok) return kNaN;
        Angle1 wrist;
        double theta;
        const Vec3 v = detail::in_plane(target_of(t2, t1, wrist, theta, 1.0), h);
        return (dot(v, v) - middle) / half_width;
    };
    auto finite_or = [](double v, double otherwise) { return std::isfinite(v) ? v : otherwise; };
    constexpr double kInf = std::numeric_limits<double>::infinity();
    auto lowest = [&](double t1, double& t2) { return finite_or(reach(t1, t2), kInf); };
    auto highest = [&](double t1, double& t2) { return finite_or(-reach(t1, t2), kInf); };
    // the samples and their refined extrema, in order round the circle from start
    constexpr double step = kTwoPi / kFamilyMembers;
    FamilyMember sample[kFamilyMembers], knots[2 * kFamilyMembers];
    for (int m = 0; m < kFamilyMembers; ++m) {
        sample[m].t1 = start + m * step;
        sample[m].f = reach(sample[m].t1, sample[m].t2);
    }
    int count = 0;
    for (int m = 0; m < kFamilyMembers; ++m) {
        knots[count++] = sample[m];
        const double before = sample[(m + kFamilyMembers - 1) % kFamilyMembers].f, here = sample[m].f,
                     after = sample[(m + 1) % kFamilyMembers].f;
        if (!(std::isfinite(before) && std::isfinite(here) && std::isfinite(after))) continue;
        const double lo = sample[m].t1 - step, hi = sample[m].t1 + step;
        FamilyMember extremum;
        if (here <= before && here <= after) {
            extremum = golden_minimum(lowest, lo, hi);
        } else if (here >= before && here >= after) {
            extremum = golden_minimum(highest, lo, hi);
            extremum.f = -extremum.f;
        } else {
            continue;
        }
        if (!std::isfinite(extremum.f)) continue;
        if (extremum.t1 < start) extremum.t1 += kTwoPi;
        knots[count++] = extremum;
    }
    std::sort(knots, knots + count, [](const FamilyMember& x, const FamilyMember& y) { return x.t1 < y.t1; });
    auto inside = [&](double f) { return std::abs(f) <= band; };  // false for NaN
    int first_out = -1;
    for (int k = 0; k < count && first_out < 0; ++k)
        if (!inside(knots[k].f)) first_out = k;
    // the pieces between knots, from one where the 2R does not reach (else the whole circle is one loop)
    FamilyMember found[2 * kFamilyMembers];
    int loops_found = 0;
    bool open = false;
    FamilyMember best{};
    auto consider = [&](const FamilyMember& x) {
        if (!open || std::abs(x.f) < std::abs(best.f)) best = x;
        open = true;
    };
    auto close = [&]() {
        if (open) found[loops_found++] = best;
        open = false;
    };
    const int from = first_out < 0 ? 0 : first_out;
    for (int k = 0; k < count; ++k) {
        const FamilyMember& x = knots[(from + k) % count];
        FamilyMember y = knots[(from + k + 1) % count];
        if (from + k + 1 == count) y.t1 += kTwoPi;  // the last piece closes the circle
        const bool in_x = inside(x.f), in_y = inside(y.f);
        if (in_x) consider(x);
        if (std::isfinite(x.f) && std::isfinite(y.f) && (x.f < 0.0) != (y.f < 0.0)) {
            const FamilyMember middle = bisect_middle(reach, x, y);
            if (inside(middle.f)) consider(middle);  // a bisection a NaN stopped may end outside
        }
        if (open && !in_y && first_out >= 0) close();
    }
    if (first_out < 0) close();  // one loop round the whole circle
    std::sort(found, found + loops_found,
              [](const FamilyMember& x, const FamilyMember& y) { return std::abs(x.f) < std::abs(y.f); });
    loops_found = std::min(loops_found, kMaxLoops);
    for (int k = 0; k < loops_found; ++k) loops[k] = found[k];
    return loops_found;
}

// The angles (t1, t2) each slot (candidate i, elbow b) of the two-angle system stands on,
// and whether it is a solution. A family (free t1) is spread over its candidates (all four
// where the quartic vanishes, the two of one t2 branch where Q has rank 1): a member of
// each of its loops (family_loops), each with both elbows, or with more loops than
// candidates one per elbow; a family the 2R reaches nowhere leaves its candidates invalid.
struct SlotAngles {
    double t1[4][2], t2[4][2];
    bool valid[4][2];
};

template <class G, class Target>
SlotAngles family_slots(const G& g, const Mat2& P, const double* r, const AngleCandidates& pair,
                        Target target_of, Vec3 a, Vec3 b) {
    SlotAngles slots{};
    for (int i = 0; i < 4; ++i)
        for (int e = 0; e < 2; ++e)
            slots.t1[i][e] = pair.t1[i], slots.t2[i][e] = pair.t2[i], slots.valid[i][e] = pair.valid[i];
    for (int branch = 0; branch < (g.rank1 ? 2 : 1); ++branch) {
        int group[4], size = 0;
        for (int i = 0; i < 4; ++i)
            if (pair.free[i] && (!g.rank1 || i % 2 == branch)) group[size++] = i;
        if (size == 0) continue;
        FamilyMember loops[kMaxLoops];
        const int count = family_loops(g, P, r, group[0], pair.t1[group[0]], target_of, a, b, loops);
        for (int k = 0; k < size; ++k)
            for (int e = 0; e < 2; ++e) {
                const int m = count <= size ? k : (2 * k + e < count ? 2 * k + e : 2 * k);
                const int i = group[k];
                slots.valid[i][e] = m < count;
                if (m < count) slots.t1[i][e] = loops[m].t1, slots.t2[i][e] = loops[m].t2;
            }
    }
    return slots;
}

}  // namespace armkit
