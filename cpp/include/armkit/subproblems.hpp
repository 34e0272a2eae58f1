// Paden-Kahan subproblems: the geometric building blocks of closed-form IK.
//
// Each function solves one instance on Vec3 values (no allocation) and returns a small
// struct. Axes k are unit vectors; rotations R(k, t) are active, right-handed, about an
// axis through the origin. A subproblem with two solutions returns both with a pair of
// ok flags: a tangent (double) solution comes once (second branch not ok), an instance
// impossible by at most kOutTolerance (rounding) counts as tangent, one within
// kTangentTolerance of tangency is solved as tangent (its double root exactly, not split by
// the square root of a rounding error), and an instance whose solutions form a whole circle
// returns the representative t = 0 with free = true.
//
// SP1 and SP2 take a length scale: a point counts as on an axis (free) within
// kFreeTolerance of the larger of its own length and the scale, so a point that is zero up
// to rounding (the wrist centre at the shoulder's centre) is free, not a random direction.
//
//   SP1  R(k, t) p = q                              1 (least squares)
//   SP2  R(k1, t1) p1 = R(k2, t2) p2                0, 1 or 2 pairs
//   SP3  |R(k, t) p1 - p2| = d                      0, 1 or 2
//   SP4  h . R(k, t) p = d                          0, 1 or 2
//   2R   R(h, ta) (a + R(h, tb) b) = v (planar)     0, 1 or 2 pairs
#pragma once

#include <algorithm>
#include <cmath>

#include "armkit/tolerances.hpp"
#include "armkit/vec.hpp"

namespace armkit {

struct Angle1 {
    double t;   // [rad], in (-pi, pi]
    bool free;  // every angle is a solution (t = 0 returned)
};

struct Angles2 {
    double t[2];  // the two branches [rad]
    bool ok[2];   // branch exists; at tangency only the first
    bool free;    // every angle is a solution (t[0] = 0 returned)
};

struct AnglePairs2 {
    double t1[2], t2[2];  // the two branches (t1, t2) [rad]
    bool ok[2];           // branch exists (one branch when the circles touch)
    bool free1, free2;    // p1 lies on k1 (t1 arbitrary, 0 returned) or p2 on k2
};

struct Planar2 {
    double ta[2], tb[2];  // the two branches (elbow one way and the other) [rad]
    bool ok[2];           // branch exists (one at a stretched or folded elbow)
    bool free;            // the middle point lies on the first axis or b on the second
};

// h . R(k, t) v = constant + cos_coeff cos t + sin_coeff sin t.
struct TrigCoeffs {
    double constant, cos_coeff, sin_coeff;
};

inline TrigCoeffs trig_coeffs(Vec3 h, Vec3 k, Vec3 v) {
    const double hk = dot(h, k), kv = dot(k, v);
    return {hk * kv, dot(h, v) - hk * kv, dot(h, cross(k, v))};
}

// SP1: the angle t with R(k, t) p = q (least squares if |p| != |q|); free where p (or q)
// lies on the axis (scale: the length scale of p and q, 0 for none). Both terms come from
// k x p and k x q alone, which keep their relative accuracy however near the axis p and q lie:
// (k x p) . q and (p - (k . p) k) . q lost it (one vector's rounding along k times the other's
// part along k: 1e-16 against a true 1e-18 where both lie 1e-9 off the axis, an aligned wrist's
// q6 then 0.5 rad off).
inline Angle1 sp1(Vec3 p, Vec3 q, Vec3 k, double scale = 0.0) {
    const Vec3 kxp = cross(k, p), kxq = cross(k, q);  // their lengths: distances from the axis
    const double free2 = kFreeTolerance * kFreeTolerance, scale2 = scale * scale;
    if (dot(kxp, kxp) <= free2 * std::max(dot(p, p), scale2) || dot(kxq, kxq) <= free2 * std::max(dot(q, q), scale2))
        return {0.0, true};
    return {std::atan2(dot(k, cross(kxp, kxq)), dot(kxp, kxq)), false};
}

// All t with a cos t + b sin t = c; size: the size of the terms. snap: within
// kTangentTolerance (of size) of tangency return the double root once; without it both branches are
// returned (for a caller that refines the angle itself). free: a = b = c = 0.
inline Angles2 solve_trig_linear(double a, double b, double c, double size, bool snap = true) {
    const double r = std::sqrt(a * a + b * b);
    if (r <= kFreeTolerance * size) {
        const bool free = std::abs(c) <= kOutTolerance * size;
        return {{0.0, 0.0}, {free, false}, free};
    }
    // c carries rounding errors of the size of the terms, so x = c / r those over r: a small
    // r (a small circle) must not turn a tangent instance into two roots ~sqrt(eps size / r)
    // apart, nor into an impossible one
    const double x = c / r, rounding = size / r;
    if (std::abs(x) > 1.0 + kOutTolerance * rounding) return {{0.0, 0.0}, {false, false}, false};
    const double phi = std::atan2(b, a);
    if (snap && std::abs(x) >= 1.0 - kTangentTolerance * rounding) {
        const double delta = x > 0 ? 0.0 : kPi;
        return {{phi + delta, phi - delta}, {true, false}, false};
    }
    const double delta = std::acos(std::min(std::max(x, -1.0), 1.0));
    return {{phi + delta, phi - delta}, {true, true}, false};
}

// SP4: all t with h . R(k, t) p = d (h any vector). d_size: the size of the terms d was
// computed from, where they are larger than d (its rounding is relative to them).
inline Angles2 sp4(Vec3 h, Vec3 p, Vec3 k, double d, double d_size = 0.0) {
    const double kp = dot(k, p), hk = dot(h, k);
    const double size = std::sqrt(dot(h, h) * dot(p, p)) + std::max(std::abs(d), d_size);
    return solve_trig_linear(dot(h, p) - hk * kp, dot(h, cross(k, p)), d - hk * kp, size);
}

// SP3: all t with |R(k, t) p1 - p2| = d (d >= 0): expanding the square gives SP4,
// p2 . R(k, t) p1 = (|p1|^2 + |p2|^2 - d^2) / 2, whose right side carries the rounding of
// its terms: where p1 (or p2) lies on the axis and |p2| = d (|p1| = d) it is 0 only to
// that rounding, and t is free (the tool point on the last axis of a planar 2R).
inline Angles2 sp3(Vec3 p1, Vec3 p2, Vec3 k, double d) {
    const double terms = 0.5 * (dot(p1, p1) + dot(p2, p2) + d * d);
    return sp4(p2, p1, k, 0.5 * (dot(p1, p1) + dot(p2, p2) - d * d), terms);
}

namespace detail {

// SP1 onto both points x = base +- gamma n: the angle atan2((k x p) . x, p_perp . x) is
// linear in gamma, four dot products instead of building both points.
inline void angles_to_branches(Vec3 kxp, Vec3 p_perp, Vec3 base, Vec3 n, double gamma, double* t) {
    const double sin0 = dot(kxp, base), sin1 = gamma * dot(kxp, n);
    const double cos0 = dot(p_perp, base), cos1 = gamma * dot(p_perp, n);
    t[0] = std::atan2(sin0 + sin1, cos0 + cos1);
    t[1] = std::atan2(sin0 - sin1, cos0 - cos1);
}

// v minus its component along the unit vector h.
inline Vec3 in_plane(Vec3 v, Vec3 h) { return v - dot(v, h) * h; }

}  // namespace detail

// SP2: all (t1, t2) with R(k1, t1) p1 = R(k2, t2) p2 for non-parallel k1, k2 (scale: the
// length scale of p1 and p2, 0 for none). The common point is x = alpha k1 + beta k2 +-
// gamma (k1 x k2); where the circles touch (gamma^2 within rounding of 0) the one pair.
inline AnglePairs2 sp2(Vec3 p1, Vec3 p2, Vec3 k1, Vec3 k2, double scale = 0.0) {
    const double c12 = dot(k1, k2);
    const double a1 = dot(k1, p1), a2 = dot(k2, p2);
    const double det = 1.0 - c12 * c12;
    Vec3 base = ((a1 - c12 * a2) / det) * k1 + ((a2 - c12 * a1) / det) * k2;
    const Vec3 n = cross(k1, k2);
    const double n1 = dot(p1, p1), n2 = dot(p2, p2);
    const double norm2 = std::max(0.5 * (n1 + n2), scale * scale);
    // gamma^2 det^2 = r1^2 det - (a2 - c12 a1)^2 with r1 = |k1 x p1| the radius of p1's
    // circle (or 1 <-> 2): no cancellation against |p|^2, so a tiny circle (a wrist near its
    // singularity) keeps its relative accuracy. Use the smaller circle.
    const Vec3 c1 = cross(k1, p1), c2 = cross(k2, p2);
    const double r1 = dot(c1, c1), r2 = dot(c2, c2);
    double gamma2;
    if (r1 <= r2) {
        const double e = a2 - c12 * a1;
        gamma2 = (r1 * det - e * e) / (det * det);
    } else {
        const double e = a1 - c12 * a2;
        gamma2 = (r2 * det - e * e) / (det * det);
    }
    const bool exists = gamma2 >= -kOutTolerance * norm2 && std::abs(n1 - n2) <= kOutTolerance * norm2;
    const double free2 = kFreeTolerance * kFreeTolerance;
    const bool free1 = r1 <= free2 * std::max(n1, scale * scale), free2_ = r2 <= free2 * std::max(n2, scale * scale);
    // gamma^2 carries rounding errors of about eps |p| r / det (r: the smaller radius): within
    // kTangentTolerance of that the circles touch, and gamma = sqrt(rounding) ~ 1e-8 |p| would
    // split the double root. Snapping moves the common point off the circles by gamma^2 / r,
    // to rounding: a tiny circle (a wrist near its singularity) keeps its two branches.
    const bool touch = gamma2 <= kTangentTolerance * std::sqrt(norm2 * std::min(r1, r2)) / det;
    double gamma = touch ? 0.0 : std::sqrt(gamma2);
    if (free1 || free2_) {  // a point on its axis stays put: the common point is that point
        base = free1 ? p1 : p2;
        gamma = 0.0;
    }
    AnglePairs2 s{{0.0, 0.0}, {0.0, 0.0}, {false, false}, free1, free2_};
    if (!free1) detail::angles_to_branches(c1, p1 - a1 * k1, base, n, gamma, s.t1);
    if (!free2_) detail::angles_to_branches(c2, p2 - a2 * k2, base, n, gamma, s.t2);
    const bool single = touch || free1 || free2_;
    s.ok[0] = exists;
    s.ok[1] = exists && !single;
    return s;
}

// All (ta, tb) with R(h, ta) (a + R(h, tb) b) = v in the plane normal to h (components
// along h are ignored: the caller makes them consistent).
inline Planar2 planar_2r(Vec3 h, Vec3 a, Vec3 b, Vec3 v) {
    a = detail::in_plane(a, h);
    b = detail::in_plane(b, h);
    v = detail::in_plane(v, h);
    const Angles2 tb = sp3(b, -1.0 * a, h, std::sqrt(dot(v, v)));
    Planar2 s{{0.0, 0.0}, {tb.t[0], tb.t[1]}, {tb.ok[0], tb.ok[1]}, tb.free};
    // ta: SP1 turning u = a + R(h, tb) b onto v. With b normal to h, R(h, tb) b = cos b +
    // sin (h x b), so (h x u) . v and u . v are linear in cos tb, sin tb.
    const double hbv = dot(cross(h, b), v), bv = dot(b, v);
    const double hav = dot(cross(h, a), v), av = dot(a, v);
    // v on the first axis (to rounding, relative to the links' size): ta is arbitrary
    if (std::sqrt(dot(v, v)) <= kFreeTolerance * (std::sqrt(dot(a, a)) + std::sqrt(dot(b, b)))) {
        s.free = true;
        return s;
    }
    for (int i = 0; i < 2; ++i) {
        const double c = std::cos(tb.t[i]), sn = std::sin(tb.t[i]);
        s.ta[i] = std::atan2(hav + c * hbv - sn * bv, av + c * bv + sn * hbv);
    }
    return s;
}

}  // namespace armkit
