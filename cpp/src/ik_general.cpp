#include "armkit/ik_general.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include "armkit/ik_cases.hpp"
#include "armkit/random.hpp"
#include "armkit/tolerances.hpp"

namespace armkit {

namespace {

//: Joints 3, 4, 5 are measured from these angles [rad]: a root at a half-angle tangent of
//: infinity (t = pi) then needs the arm to stand at offset + pi, which a generic pose does
//: not ask. Any values do; these are far from 0, pi/2, pi and from each other.
constexpr double kGeneralOffsets[3] = {0.3, 0.7, 1.1};

// The three sample angles of a three-point DFT and the matrix taking samples to the
// coefficients of (1, cos t, sin t).
constexpr double kSamples[3] = {0.0, 2.0 * kPi / 3.0, 4.0 * kPi / 3.0};
constexpr double kS = 0.57735026918962576451;  // 1 / sqrt(3)
constexpr double kFromSamples[3][3] = {{1.0 / 3, 1.0 / 3, 1.0 / 3}, {2.0 / 3, -1.0 / 3, -1.0 / 3}, {0.0, kS, -kS}};
// (1 + x^2) (a + b cos t + c sin t) with x = tan(t / 2): rows are powers of x, columns (1, cos, sin).
constexpr double kHalfAngle[3][3] = {{1, 1, 0}, {0, 0, 2}, {1, -1, 0}};
// A prismatic joint on the right side: its quantities are quadratic in the slide d (p moves by
// d h: p.p and (p.p) l - 2 (p.l) p are of degree two), sampled at x = d / size = 0, 1, -1 and
// fitted to the coefficients of (1, x, x^2).
constexpr double kSlides[3] = {0.0, 1.0, -1.0};
constexpr double kFromSlides[3][3] = {{1, 0, 0}, {0, 0.5, -0.5}, {-1, 0.5, 0.5}};

// exp(xi q) applied to a point: the joint (h, p) turns x by q about its line.
Vec3 turn_point(Vec3 h, Vec3 p, double q, Vec3 x) { return p + rotate(h, q, x - p); }

// The 14 quantities of a point p and a direction l.
void quantities(Vec3 p, Vec3 l, double* out) {
    const double pp = dot(p, p), pl = dot(p, l);
    const Vec3 pxl = cross(p, l), last = pp * l - (2.0 * pl) * p;
    const double v[kQuantities] = {p.x, p.y, p.z, l.x, l.y, l.z, pp, pl, pxl.x, pxl.y, pxl.z, last.x, last.y, last.z};
    std::copy(v, v + kQuantities, out);
}

using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat24 = Eigen::Matrix<double, 24, 24>;
using Mat14x8 = Eigen::Matrix<double, kQuantities, 8>;
using Vec14 = Eigen::Matrix<double, kQuantities, 1>;

// The line (x, l) moved back by loop joint k's sample a: turned by -angle, or slid by -d.
void undo_sample(const Vec3* h, const Vec3* p, const bool* prismatic, double size, int k, int a, Vec3& x, Vec3& l) {
    if (prismatic[k]) {
        x = x - (kSlides[a] * size) * h[k];
        return;
    }
    x = turn_point(h[k], p[k], -kSamples[a], x);
    l = rotate(h[k], -kSamples[a], l);
}

// The right side's coefficients over (1, cos, sin) of q1, q2 (no offsets), or over (1, x, x^2)
// of a prismatic one, for the image (gp, gh) of the line of axis 6.
void right_side(const Vec3* h, const Vec3* p, const bool* prismatic, double size, Vec3 gp, Vec3 gh,
                double (&right)[kQuantities][3][3]) {
    double samples[3][3][kQuantities];
    for (int a = 0; a < 3; ++a) {
        Vec3 p1 = gp, l1 = gh;
        undo_sample(h, p, prismatic, size, 0, a, p1, l1);
        for (int b = 0; b < 3; ++b) {
            Vec3 p2 = p1, l2 = l1;
            undo_sample(h, p, prismatic, size, 1, b, p2, l2);
            quantities(p2, l2, samples[a][b]);
        }
    }
    const double(*fit1)[3] = prismatic[0] ? kFromSlides : kFromSamples;
    const double(*fit2)[3] = prismatic[1] ? kFromSlides : kFromSamples;
    for (int z = 0; z < kQuantities; ++z)
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                double s = 0.0;
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) s += fit1[i][a] * fit2[j][b] * samples[a][b][z];
                right[z][i][j] = s;
            }
}

// The angle of the loop's last joint from the rotation left once the others (q, 5) are known.
double sixth_angle(const Vec3* h, const bool* prismatic, const Mat3& R, const double* q) {
    const Vec3 h6 = h[5];
    const Vec3 axis = std::fabs(h6.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    Vec3 u = cross(h6, axis);
    u = (1.0 / norm(u)) * u;
    Vec3 v = R * u;  // R6 u = R5^T ... R1^T R u
    for (int j = 0; j < 5; ++j)
        if (!prismatic[j]) v = rotate(h[j], -q[j], v);
    return std::atan2(dot(h6, cross(u, v)), dot(u, v));
}


// A vector z (12) with A z = 0 for a singular A. LU with partial pivoting, P A = L U: where its
// smallest pivot U(k, k) is at most kNullPivotGap of the next smallest, it stands for the zero
// one, and z_k = 1, z_j = 0 for j > k, the rows above by back substitution (A z = P^T L U(k, k)
// e_k: the pivot's size, |L| <= 1). Else (partial pivoting need not reveal the rank) full-pivot
// LU, P A Q = L U, then U w = 0 with w_11 = 1, z = Q w. The partial one is a quarter of the cost.
void back_substitute(const Mat12& U, int k, Eigen::Matrix<double, 12, 1>& w) {
    w.setZero();
    w(k) = 1.0;
    for (int i = k - 1; i >= 0; --i) {
        double s = 0.0;
        for (int j = i + 1; j <= k; ++j) s += U(i, j) * w(j);
        w(i) = U(i, i) != 0.0 ? -s / U(i, i) : 0.0;
    }
}

void null_vector(const Mat12& A, Eigen::Matrix<double, 12, 1>& z) {
    const Eigen::PartialPivLU<Mat12> partial(A);
    const Mat12& LU = partial.matrixLU();
    int k = 0;
    double smallest = std::fabs(LU(0, 0)), next = std::numeric_limits<double>::infinity();
    for (int i = 1; i < 12; ++i) {
        const double pivot = std::fabs(LU(i, i));
        if (pivot < smallest) next = smallest, smallest = pivot, k = i;
        else next = std::min(next, pivot);
    }
    if (next > 0.0 && smallest <= kNullPivotGap * next) {
        back_substitute(LU, k, z);
        return;
    }
    const Eigen::FullPivLU<Mat12> full(A);
    Eigen::Matrix<double, 12, 1> w;
    back_substitute(full.matrixLU(), 11, w);
    z = full.permutationQ() * w;
}

using Mat16 = Eigen::Matrix<double, 16, 16>;
using Mat12x24 = Eigen::Matrix<double, 12, 24>;

// The companion matrix C = [0 I; K] of the pencil restricted to the complement of its
// eigenvalues +-i (the spurious roots, see spurious_bases), into A; false where they do not
// split off to kSpuriousSplit (then C keeps them). With Q = [Q1 Q2] (Q1 spanning their real
// invariant subspace) Q^T C Q = [* *; 0 A], A = Q2^T C Q2: an orthogonal similarity, no digits
// lost, and 16 x 16 for the eigensolver instead of 24 x 24.
bool without_spurious_roots(const Mat12x24& K, const double* basis, Mat16& A) {
    const Eigen::Map<const Mat24> Q(basis);
    const Mat12x24 KQ = K * Q;
    // C Q = [Q's bottom rows; K Q]
    const Eigen::Matrix<double, 16, 8> leak = Q.topRightCorner<12, 16>().transpose() * Q.bottomLeftCorner<12, 8>() +
                                              Q.bottomRightCorner<12, 16>().transpose() * KQ.leftCols<8>();
    if (!(leak.cwiseAbs().maxCoeff() <= kSpuriousSplit * std::max(1.0, K.cwiseAbs().maxCoeff()))) return false;
    A.noalias() = Q.topRightCorner<12, 16>().transpose() * Q.bottomRightCorner<12, 16>();
    A.noalias() += Q.bottomRightCorner<12, 16>().transpose() * KQ.rightCols<16>();
    return true;
}

// The real roots of det(M0 + M1 x + M2 x^2) as angles t = 2 atan(x) (x = infinity: t = pi)
// into t (at most kGeneralRoots, the most nearly real first); returns their number. A
// companion matrix of the better conditioned of M2 (roots x) and M0 (roots 1 / x), without
// the spurious roots +-i where the arm has their subspace (spurious: per arm, see
// spurious_bases; null: none), goes to Eigen's real Schur eigenvalue solver; where both are
// nearly singular, Eigen's QZ takes the pencil itself.
int half_angle_roots(const Mat12 (&M)[3], const double (*spurious)[24 * 24], double* t) {
    const Eigen::PartialPivLU<Mat12> lead(M[2]), trail(M[0]);
    const double rc_lead = lead.rcond(), rc_trail = trail.rcond();
    std::complex<double> x[24];  // eigenvalues, as x = tan(t / 2) or as 1 / x
    int eigenvalues = 24;
    bool inverted = false;
    if (std::max(rc_lead, rc_trail) >= kCompanionCondition) {
        inverted = rc_trail > rc_lead;
        const Eigen::PartialPivLU<Mat12>& lu = inverted ? trail : lead;
        Mat12x24 K;  // C's bottom rows
        K.leftCols<12>() = -lu.solve(inverted ? M[2] : M[0]);
        K.rightCols<12>() = -lu.solve(M[1]);
        Mat16 A;
        if (spurious && without_spurious_roots(K, spurious[inverted], A)) {
            const Eigen::EigenSolver<Mat16> eig(A, false);
            if (eig.info() != Eigen::Success) return 0;
            eigenvalues = 16;
            for (int r = 0; r < 16; ++r) x[r] = eig.eigenvalues()(r);
        } else {
            Mat24 C = Mat24::Zero();
            C.topRightCorner<12, 12>().setIdentity();
            C.bottomRows<12>() = K;
            const Eigen::EigenSolver<Mat24> eig(C, false);
            if (eig.info() != Eigen::Success) return 0;
            for (int r = 0; r < 24; ++r) x[r] = eig.eigenvalues()(r);
        }
    } else {
        Mat24 A = Mat24::Zero(), B = Mat24::Zero();
        A.topRightCorner<12, 12>().setIdentity();
        A.bottomLeftCorner<12, 12>() = -M[0];
        A.bottomRightCorner<12, 12>() = -M[1];
        B.topLeftCorner<12, 12>().setIdentity();
        B.bottomRightCorner<12, 12>() = M[2];
        const Eigen::GeneralizedEigenSolver<Mat24> qz(A, B, false);
        if (qz.info() != Eigen::Success) return 0;
        for (int r = 0; r < 24; ++r) {
            const double beta = qz.betas()(r);
            // beta ~ 0: a root at infinity, taken as 1 / x = 0
            const std::complex<double> alpha = qz.alphas()(r);
            x[r] = std::fabs(beta) > kInfiniteEigenvalue * std::abs(alpha) ? alpha / beta : std::complex<double>(1e300, 0.0);
        }
    }
    int order[24], count = 0;
    double imag[24];
    for (int r = 0; r < eigenvalues; ++r) {
        imag[r] = std::fabs(x[r].imag()) / std::max(1.0, std::abs(x[r]));
        if (imag[r] <= kRealRoot && x[r].imag() >= 0.0 && std::isfinite(x[r].real())) order[count++] = r;
    }
    std::sort(order, order + count, [&](int a, int b) { return imag[a] < imag[b]; });
    count = std::min(count, kGeneralRoots);
    for (int c = 0; c < count; ++c) {
        const double v = x[order[c]].real();
        t[c] = inverted ? 2.0 * std::atan2(1.0, v) : 2.0 * std::atan(v);
    }
    return count;
}
// The left side's coefficients over (1, cos, sin) of t3, t4, t5 for the loop's joints h, p (6).
void left_side(const Vec3* h, const Vec3* p, double (&left)[kQuantities][3][3][3]) {
    double samples[3][3][3][kQuantities];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            for (int c = 0; c < 3; ++c) {
                const double q3 = kGeneralOffsets[0] + kSamples[a], q4 = kGeneralOffsets[1] + kSamples[b],
                             q5 = kGeneralOffsets[2] + kSamples[c];
                Vec3 x = turn_point(h[4], p[4], q5, p[5]), l = rotate(h[4], q5, h[5]);
                x = turn_point(h[3], p[3], q4, x);
                l = rotate(h[3], q4, l);
                quantities(turn_point(h[2], p[2], q3, x), rotate(h[2], q3, l), samples[a][b][c]);
            }
    for (int z = 0; z < kQuantities; ++z)
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                for (int k = 0; k < 3; ++k) {
                    double s = 0.0;
                    for (int a = 0; a < 3; ++a)
                        for (int b = 0; b < 3; ++b)
                            for (int c = 0; c < 3; ++c)
                                s += kFromSamples[i][a] * kFromSamples[j][b] * kFromSamples[k][c] * samples[a][b][c][z];
                    left[z][i][j][k] = s;
                }
}

// The orthogonal bases Q (24 x 24, column-major) whose first eight columns span the real
// invariant subspace of the companion matrix for its eigenvalues y = +-i: bases[0] for y = x3,
// bases[1] for y = 1 / x3. det M(x3) holds the spurious factor (1 + x3^2)^4, semisimple: M(i)
// has a null space of four dimensions, and it depends on the arm alone, since at x3 = i the
// factor 1 + x3^2 of the constant term (the only one holding the pose) vanishes: every
// quantity of the left side, as a row over the monomials x4^a x5^b and times x4, annihilates
// it (28 rows; a real 56 x 24 system of rank 16 for v = a + i b). The companion's eigenvectors
// are [u; i u] with u = v for y = x3 and u = conj(v) for y = 1 / x3 (P(y) = y^2 M(1 / y)):
// real parts [a; -b] and [a; b].
void spurious_bases(const double (&left)[kQuantities][3][3][3], double (&bases)[2][24 * 24]) {
    Eigen::Matrix<double, 56, 24> L = Eigen::Matrix<double, 56, 24>::Zero();
    for (int z = 0; z < kQuantities; ++z)
        for (int p4 = 0; p4 < 3; ++p4)
            for (int p5 = 0; p5 < 3; ++p5) {
                // at x3 = i: (1 + x3^2, 1 - x3^2, 2 x3) = (0, 2, 2 i) on (1, cos, sin) of t3
                double re = 0.0, im = 0.0;
                for (int j = 0; j < 3; ++j)
                    for (int k = 0; k < 3; ++k) {
                        const double w = 2.0 * kHalfAngle[p4][j] * kHalfAngle[p5][k];
                        re += w * left[z][1][j][k];
                        im += w * left[z][2][j][k];
                    }
                for (int times = 0; times < 2; ++times) {  // the quantity, and times x4
                    const int row = 2 * z + times, col = 3 * (p4 + times) + p5;
                    L(row, col) = re, L(row, 12 + col) = -im;
                    L(28 + row, col) = im, L(28 + row, 12 + col) = re;
                }
            }
    // the null space from the LU (P L Q = L U, U's rows past 16 ~0): U11 w = -U12, [a; b] = Q [w; I]
    const Eigen::FullPivLU<Eigen::Matrix<double, 56, 24>> lu(L);
    const auto U = lu.matrixLU().topRows<24>();
    Eigen::Matrix<double, 24, 8> X;
    X.bottomRows<8>().setIdentity();
    X.topRows<16>() = -U.topLeftCorner<16, 16>().triangularView<Eigen::Upper>().solve(U.topRightCorner<16, 8>());
    X = lu.permutationQ() * X;
    for (int inverted = 0; inverted < 2; ++inverted) {
        Eigen::Matrix<double, 24, 8> Y = X;
        if (!inverted) Y.bottomRows<12>() *= -1.0;
        Eigen::Map<Mat24> Q(bases[inverted]);
        Q = Eigen::HouseholderQR<Eigen::Matrix<double, 24, 8>>(Y).householderQ();
    }
}

}  // namespace

bool loop_takes(const CaseChain& chain, int shift) {
    int slides = 0;
    for (int k = 0; k < 6; ++k) {
        if (!chain.prismatic[(k + shift) % 6]) continue;
        if (k >= 2) return false;  // the left side's joints and joint 6 turn
        ++slides;
    }
    return slides <= 1;
}

void prepare_general(const CaseChain& chain, int shift, GeneralSixR& g) {
    std::copy(chain.h, chain.h + 6, g.h);
    std::copy(chain.p, chain.p + 6, g.p);
    for (int j = 0; j < 6; ++j) g.prismatic[j] = chain.prismatic[j];
    g.size = chain.size;
    g.shift = shift;
    if (shift == 0) {
        left_side(g.h, g.p, g.left);
        spurious_bases(g.left, g.spurious);
    }
}

int general_six_r(const GeneralSixR& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    std::fill(valid, valid + kGeneralRoots, false);
    std::fill(family, family + kGeneralRoots, false);
    std::fill(q, q + kGeneralRoots * 6, 0.0);
    for (int r = 0; r < 3; ++r)
        if (!std::isfinite(dot(R.r[r], R.r[r]) + t.x + t.y + t.z)) return 0;
    // the loop e_{s+1} ... e_6 e_1' ... e_s' = G, e' = G^-1 e G moving about (along) G^-1 of its line
    Vec3 h[6], p[6];
    bool prismatic[6];  // only loop joints 1, 2 can be (loop_takes)
    for (int k = 0; k < 6; ++k) {
        const int j = (k + g.shift) % 6;
        const bool moved = k >= 6 - g.shift;
        h[k] = moved ? mul_transposed(R, g.h[j]) : g.h[j];
        p[k] = moved ? mul_transposed(R, g.p[j] - t) : g.p[j];
        prismatic[k] = g.prismatic[j];
    }
    double left[kQuantities][3][3][3];
    if (g.shift == 0)
        std::copy(&g.left[0][0][0][0], &g.left[0][0][0][0] + kQuantities * 27, &left[0][0][0][0]);
    else
        left_side(h, p, left);
    double right[kQuantities][3][3];
    right_side(h, p, prismatic, g.size, R * p[5] + t, R * h[5], right);

    // left - constant of the right = Q y, y the 8 monomials of q1, q2 other than 1
    Mat14x8 Q;
    for (int z = 0; z < kQuantities; ++z) {
        left[z][0][0][0] -= right[z][0][0];
        for (int m = 1; m < 9; ++m) Q(z, m - 1) = right[z][m / 3][m % 3];
    }
    const Eigen::ColPivHouseholderQR<Mat14x8> qr(Q);
    Eigen::Matrix<double, kQuantities, 6> basis_q = Eigen::Matrix<double, kQuantities, 6>::Zero();
    basis_q.bottomRows<6>().setIdentity();
    basis_q.applyOnTheLeft(qr.householderQ());  // the last 6 columns of the QR's Q
    const Eigen::Matrix<double, 6, kQuantities> N = basis_q.transpose();  // N Q = 0

    // 6 equations over (1, cos, sin)^3, then over powers of x3, x4, x5 (times the denominators)
    double E[6][3][3][3];
    for (int e = 0; e < 6; ++e)
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                for (int k = 0; k < 3; ++k) {
                    double s = 0.0;
                    for (int z = 0; z < kQuantities; ++z) s += N(e, z) * left[z][i][j][k];
                    E[e][i][j][k] = s;
                }
    Mat12 M[3];
    for (auto& m : M) m.setZero();
    for (int e = 0; e < 6; ++e) {
        // kHalfAngle on t5, then t4, then t3 (one joint at a time)
        double a[3][3][3], b[3][3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                for (int p5 = 0; p5 < 3; ++p5)
                    a[i][j][p5] = kHalfAngle[p5][0] * E[e][i][j][0] + kHalfAngle[p5][1] * E[e][i][j][1] +
                                  kHalfAngle[p5][2] * E[e][i][j][2];
        for (int i = 0; i < 3; ++i)
            for (int p4 = 0; p4 < 3; ++p4)
                for (int p5 = 0; p5 < 3; ++p5)
                    b[i][p4][p5] = kHalfAngle[p4][0] * a[i][0][p5] + kHalfAngle[p4][1] * a[i][1][p5] +
                                   kHalfAngle[p4][2] * a[i][2][p5];
        for (int p3 = 0; p3 < 3; ++p3)
            for (int p4 = 0; p4 < 3; ++p4)
                for (int p5 = 0; p5 < 3; ++p5) {
                    const double s = kHalfAngle[p3][0] * b[0][p4][p5] + kHalfAngle[p3][1] * b[1][p4][p5] +
                                     kHalfAngle[p3][2] * b[2][p4][p5];
                    for (int shift = 0; shift < 2; ++shift) M[p3](e + 6 * shift, (p4 + shift) * 3 + p5) = s;
                }
    }

    // det(M0 + M1 x + M2 x^2) = 0: the roots x3 = tan(t3 / 2) as angles t3
    double roots[24];
    const int count = half_angle_roots(M, g.shift == 0 ? g.spurious : nullptr, roots);

    int found = 0;
    for (int c = 0; c < count; ++c) {
        const double t3 = roots[c];
        const double x3 = std::tan(0.5 * t3);
        // the monomials x4^i x5^j (index 3 i + j): the null vector of M(x3) (or of M(x3) / x3^2)
        const double w0 = std::fabs(x3) <= 1.0 ? 1.0 : 1.0 / (x3 * x3);
        const Mat12 Mx = w0 * M[0] + (w0 * x3) * M[1] + (w0 * x3 * x3) * M[2];
        Eigen::Matrix<double, 12, 1> z;
        null_vector(Mx, z);
        // x4 = z(m + 3) / z(m) and x5 = z(m + 1) / z(m) from the largest such pair, as angles
        // by atan2 (x4 = infinity, t4 = pi, leaves only the x4^3 row non-zero)
        int i4 = 0, i5 = 0;
        for (int m = 0; m < 12; ++m) {
            if (m / 3 <= 2 && std::fabs(z(m)) + std::fabs(z(m + 3)) > std::fabs(z(i4)) + std::fabs(z(i4 + 3))) i4 = m;
            if (m % 3 <= 1 && std::fabs(z(m)) + std::fabs(z(m + 1)) > std::fabs(z(i5)) + std::fabs(z(i5 + 1))) i5 = m;
        }
        const double t4 = 2.0 * std::atan2(z(i4 + 3), z(i4));
        const double t5 = 2.0 * std::atan2(z(i5 + 1), z(i5));
        // q1, q2 from Q y = left(t3, t4, t5)
        const double trig[3][3] = {{1.0, std::cos(t3), std::sin(t3)}, {1.0, std::cos(t4), std::sin(t4)},
                                   {1.0, std::cos(t5), std::sin(t5)}};
        Vec14 rhs;
        for (int zq = 0; zq < kQuantities; ++zq) {
            double s = 0.0;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    for (int k = 0; k < 3; ++k) s += left[zq][i][j][k] * trig[0][i] * trig[1][j] * trig[2][k];
            rhs(zq) = s;
        }
        // monomial m of (1, c1, s1) x (1, c2, s2) at y(m - 1); a slide's (1, x, x^2) for its (1, c, s)
        const Eigen::Matrix<double, 8, 1> y = qr.solve(rhs);
        double loop[6];  // in the loop's order
        loop[0] = prismatic[0] ? g.size * y(2) : std::atan2(y(5), y(2));
        loop[1] = prismatic[1] ? g.size * y(0) : std::atan2(y(1), y(0));
        loop[2] = wrap_angle(kGeneralOffsets[0] + t3);
        loop[3] = wrap_angle(kGeneralOffsets[1] + t4);
        loop[4] = wrap_angle(kGeneralOffsets[2] + t5);
        loop[5] = sixth_angle(h, prismatic, R, loop);
        double* row = q + 6 * found;
        bool finite = true;
        for (int k = 0; k < 6; ++k) {
            row[(k + g.shift) % 6] = loop[k];
            finite = finite && std::isfinite(loop[k]);
        }
        if (!finite) continue;
        valid[found++] = true;
    }
    return found;
}

// ---------------------------------------------------------------- a class nearby

struct ClassSeed {
    CaseGeometry geometry;  // the class, on the arm moved onto it
    ArmLines lines;         // the lines its geometry works on
    ArmLines general;       // the general loop's lines
};

namespace {

// How far apart values a and b of the chain's joint j are: an angle [rad] wrapped, a slide
// over the arm's size.
double joint_gap(const CaseChain& chain, int j, double a, double b) {
    return chain.prismatic[j] ? std::fabs(a - b) / chain.size : std::fabs(wrap_angle(a - b));
}

// Whether rows a and b (6 joints of chain) are within gap of each other in every joint.
bool close_rows(const CaseChain& chain, const double* a, const double* b, double gap) {
    for (int j = 0; j < 6; ++j)
        if (!(joint_gap(chain, j, a[j], b[j]) <= gap)) return false;
    return true;
}

// The seed's class candidates for the general loop's joint motion (R, t), in the loop's
// joints, first in q (kGeneralRoots x 6), then the `found` candidates of the elimination
// that are not within kLoopNear of one, as long as there is room.
void add_class_candidates(const ClassSeed& s, const Mat3& R, Vec3 t, double* q, bool* valid, int found) {
    Pose G;
    for (int r = 0; r < 3; ++r) {
        G(r, 0) = R.r[r].x, G(r, 1) = R.r[r].y, G(r, 2) = R.r[r].z;
    }
    G(0, 3) = t.x, G(1, 3) = t.y, G(2, 3) = t.z;
    const Pose A = compose(G, s.general.M);  // T, or T^-1 for an inverted loop
    const Pose T = s.general.inverted ? inverse(A) : A;
    const Pose Gc = compose(s.lines.inverted ? inverse(T) : T, inverse(s.lines.M));
    double qc[kMaxCandidates * 6];
    bool vc[kMaxCandidates], fc[kMaxCandidates];
    solve_pose(s.geometry, Gc.rotation(), Gc.position(), qc, vc, fc);
    double rows[kGeneralRoots * 6];
    int count = 0;
    for (int c = 0; c < case_entry(s.geometry).candidates && count < kGeneralRoots; ++c) {
        if (!vc[c]) continue;
        double user[6], *row = rows + 6 * count;
        for (int j = 0; j < 6; ++j) user[s.lines.index[j]] = s.lines.sign[j] * qc[6 * c + j];
        bool finite = true;
        for (int j = 0; j < 6; ++j) {
            row[j] = s.general.sign[j] * user[s.general.index[j]];
            finite = finite && std::isfinite(row[j]);
        }
        count += finite;
    }
    const int seeded = count;
    for (int r = 0; r < found && count < kGeneralRoots; ++r) {
        bool near = false;
        for (int c = 0; c < seeded && !near; ++c) near = close_rows(s.general, q + 6 * r, rows + 6 * c, kLoopNear);
        if (!near) std::copy(q + 6 * r, q + 6 * r + 6, rows + 6 * count++);
    }
    std::copy(rows, rows + 6 * count, q);
    for (int r = 0; r < kGeneralRoots; ++r) valid[r] = r < count;
}

// The class within kNearClass of arm (spherical, three-parallel, parallel-base), moved onto it
// exactly and detected there by its own detect function, for the general loop `general`; or none.
std::shared_ptr<const ClassSeed> near_class_seed(const ArmLines& arm, const ArmLines& general) {
    ArmLines loose = arm;
    loose.tolerance = kNearClass;
    for (const CaseEntry& entry : kCases) {
        ArmLines snapped;
        if (!entry.whole_pose || std::string(entry.name) == "general" || std::string(entry.name) == "planar" ||
            !snap_to_class(loose, entry.name, snapped))
            continue;
        CaseDetection found = entry.detect(snapped);
        if (auto* f = std::get_if<CaseFound>(&found))
            return std::make_shared<ClassSeed>(ClassSeed{f->geometry, f->lines, general});
    }
    return nullptr;
}

}  // namespace

void solve_case(const GeneralGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    const int found = general_six_r(*g.arm, R, t, q, valid, family);
    if (g.seed) add_class_candidates(*g.seed, R, t, q, valid, found);
}

// ------------------------------------------------------------------------ detection

namespace {

//: Configurations on which detect_general compares the loops.
constexpr int kLoopSamples = 12;

// The tool pose of lines `arm` at q (user's joints = internal here: arm not reversed):
// exp(xi_1 q_1) ... exp(xi_n q_n) M.
Pose lines_pose(const ArmLines& arm, const double* q) {
    Pose T = arm.M;
    for (int j = arm.n - 1; j >= 0; --j) {
        Pose next;
        for (int c = 0; c < 4; ++c) {
            const Vec3 v = T.column(c);
            Vec3 moved;
            if (c < 3) moved = arm.prismatic[j] ? v : rotate(arm.h[j], q[j], v);
            else moved = arm.prismatic[j] ? v + q[j] * arm.h[j] : turn_point(arm.h[j], arm.p[j], q[j], v);
            next(0, c) = moved.x, next(1, c) = moved.y, next(2, c) = moved.z;
        }
        T = next;
    }
    return T;
}

GeneralGeometry general_geometry(const ArmLines& lines, int shift) {
    GeneralGeometry g;
    static_cast<CaseChain&>(g) = lines;
    auto arm = std::make_shared<GeneralSixR>();
    prepare_general(lines, shift, *arm);
    g.arm = std::move(arm);
    return g;
}

}  // namespace

Detection<GeneralGeometry> detect_general(const ArmLines& arm) {
    if (arm.n != 6)
        return CaseReason{CaseFit::Joints, "the general solver needs 6 joints, not " + std::to_string(arm.n)};
    int slides = 0;
    for (int j = 0; j < 6; ++j) slides += arm.prismatic[j];
    if (slides > 1)
        return CaseReason{CaseFit::Prismatic, std::to_string(slides) + " joints are prismatic: the general solver "
                                              "takes one at most; use numeric IK"};
    Random random(0);
    double q[kLoopSamples][6];
    Pose T[kLoopSamples];
    for (int s = 0; s < kLoopSamples; ++s) {
        for (int j = 0; j < 6; ++j) {  // a slide within half the arm's size
            const double u = random.uniform(-kPi, kPi);
            q[s][j] = arm.prismatic[j] ? 0.5 * arm.size * u / kPi : u;
        }
        T[s] = lines_pose(arm, q[s]);
    }
    const ArmLines loops[2] = {arm, reversed(arm)};
    double best_worst = 0.0, best_mean = 0.0;
    int best = -1, best_near = 0;
    for (int l = 0; l < 12; ++l) {
        const ArmLines& lines = loops[l / 6];
        if (!loop_takes(lines, l % 6)) continue;
        const GeneralGeometry g = general_geometry(lines, l % 6);
        const Pose M_inv = inverse(lines.M);
        double worst = 0.0, mean = 0.0;
        int near = 0;  // distinct raw candidates near a solution, over the samples
        for (int s = 0; s < kLoopSamples; ++s) {
            const Pose G = compose(lines.inverted ? inverse(T[s]) : T[s], M_inv);
            double found[kGeneralRoots * 6];
            bool valid[kGeneralRoots], family[kGeneralRoots];
            solve_case(g, G.rotation(), G.position(), found, valid, family);
            double closest = kPi, kept[kGeneralRoots * 6];
            int count = 0;
            for (int c = 0; c < kGeneralRoots; ++c) {
                if (!valid[c]) continue;
                const double* row = found + 6 * c;
                double gap = 0.0, user[6];
                for (int j = 0; j < 6; ++j) {
                    gap = std::max(gap, joint_gap(lines, j, row[j], lines.sign[j] * q[s][lines.index[j]]));
                    user[lines.index[j]] = lines.sign[j] * row[j];
                }
                closest = std::min(closest, gap);
                const Pose F = lines_pose(arm, user);
                double residual = 0.0;
                for (int a = 0; a < 12; ++a) residual = std::max(residual, std::fabs(F.m[a] - T[s].m[a]));
                bool twin = false;
                for (int k = 0; k < count && !twin; ++k) {
                    double apart = 0.0;
                    for (int j = 0; j < 6; ++j)
                        apart = std::max(apart, joint_gap(lines, j, kept[6 * k + j], row[j]));
                    twin = apart <= kLoopNear;
                }
                if (residual <= kLoopNear * arm.scale && !twin) std::copy(row, row + 6, kept + 6 * count++);
            }
            near += count;
            worst = std::max(worst, closest);
            mean += closest / kLoopSamples;
        }
        // the loop whose raw candidates come closest to every sample's configuration (worst
        // sample, then mean), then the one with more distinct candidates near a solution:
        // ranking by that count first picked a loop that loses a root beside a near-double one
        // (a UR5 with its lines moved by 3e-6, q5 = 1e-3: 7 of 8 solutions)
        if (best < 0 || worst < best_worst ||
            (worst == best_worst && (mean < best_mean || (mean == best_mean && near > best_near))))
            best = l, best_near = near, best_worst = worst, best_mean = mean;
        if (worst <= kGoodLoop) break;
    }
    GeneralGeometry chosen = general_geometry(loops[best / 6], best % 6);
    chosen.seed = near_class_seed(arm, loops[best / 6]);
    const std::string near = chosen.seed ? std::string(" (within 1e-6 of the ") + case_entry(chosen.seed->geometry).name +
                                               " case, whose solutions on the arm moved onto it seed it)"
                                         : std::string();
    // a 6R arm here is in no class; a 5R1P arm may have meeting or parallel axes still
    const std::string what = slides ? "general 6-joint arm with a prismatic joint (5R1P): in no class (a class "
                                      "takes a slide only as the Stanford arm's or a SCARA's joint 3)"
                                    : "general 6R arm: no three consecutive axes meet at one point or are "
                                      "parallel to rounding";
    return CaseMatch<GeneralGeometry>{chosen, loops[best / 6], slides ? "general-5r1p" : "general-6r",
                                      what + "; every solution by Raghavan-Roth elimination (a 24 x 24 "
                                      "eigenproblem)" + near + ", up to 16 solutions",
                                      true};
}

}  // namespace armkit
