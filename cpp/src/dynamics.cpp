#include "armkit/dynamics.hpp"

#include <cmath>

#include "armkit/linalg.hpp"

namespace armkit {

namespace {

// Pose of F_i in F_{i-1}: L_{i-1} M_i(q_i), as its rotation R and origin p.
struct Step {
    Mat3 R;
    Vec3 p;
};

Step joint_step(const Chain& chain, int i, double q) {
    const Pose& L = chain.between[std::size_t(i)];
    Step s{L.rotation(), L.position()};
    if (chain.prismatic[std::size_t(i)]) {
        s.p = s.p + q * L.column(2);
    } else {  // R Rz(q): the first two columns turn by q
        const double c = std::cos(q), sn = std::sin(q);
        for (auto& row : s.R.r) {
            const double x = row.x, y = row.y;
            row.x = c * x + sn * y;
            row.y = -sn * x + c * y;
        }
    }
    return s;
}

constexpr Vec3 kZ{0.0, 0.0, 1.0};

Mat3 rotate_tensor(const Mat3& R, const Mat3& I) {  // R I R^T
    Mat3 RI, out;
    for (int r = 0; r < 3; ++r) RI.r[r] = mul_transposed(I, R.r[r]);  // row r of R I (I symmetric)
    for (int r = 0; r < 3; ++r) out.r[r] = R * RI.r[r];                // (R I R^T)_{r,k} = R_k . (R I)_r
    return out;
}

// A composite body (m, h, I_o) of frame F_i moved into F_{i-1} by (R, p):
// h' = R h + m p, I' = R I R^T + 2 (h.p) 1 - p h^T - h p^T + m (|p|^2 1 - p p^T), with h = R h.
void add_moved(const Step& s, double m, Vec3 h, const Mat3& I, double& m_out, Vec3& h_out, Mat3& I_out) {
    const Vec3 hr = s.R * h, p = s.p;
    const Mat3 Ir = rotate_tensor(s.R, I);
    const double diagonal = 2.0 * dot(hr, p) + m * dot(p, p);
    const double pv[3] = {p.x, p.y, p.z}, hv[3] = {hr.x, hr.y, hr.z};
    for (int r = 0; r < 3; ++r) {
        double* out = &I_out.r[r].x;
        const double* in = &Ir.r[r].x;
        for (int k = 0; k < 3; ++k)
            out[k] += in[k] + (r == k ? diagonal : 0.0) - pv[r] * hv[k] - hv[r] * pv[k] - m * pv[r] * pv[k];
    }
    m_out += m;
    h_out = h_out + hr + m * p;
}

}  // namespace

void inverse_dynamics(const Dynamics& model, const double* q, const double* qd, const double* qdd, Vec3 gravity,
                      double* tau) {
    const Chain& chain = model.chain;
    const int n = chain.n;
    Step steps[kMaxJoints];
    Vec3 force[kMaxJoints], torque[kMaxJoints];
    Vec3 w{}, wd{}, a = -gravity;  // the base accelerates upwards: gravity on every body
    for (int i = 0; i < n; ++i) {
        const Step s = steps[i] = joint_step(chain, i, q[i]);
        const double v = qd ? qd[i] : 0.0, acc = qdd ? qdd[i] : 0.0;
        const Vec3 a_origin = mul_transposed(s.R, a + cross(wd, s.p) + cross(w, cross(w, s.p)));
        const Vec3 w_parent = mul_transposed(s.R, w), wd_parent = mul_transposed(s.R, wd);
        if (chain.prismatic[std::size_t(i)]) {
            w = w_parent;
            wd = wd_parent;
            a = a_origin + 2.0 * v * cross(w, kZ) + Vec3{0.0, 0.0, acc};
        } else {
            w = w_parent + Vec3{0.0, 0.0, v};
            wd = wd_parent + v * cross(w_parent, kZ) + Vec3{0.0, 0.0, acc};
            a = a_origin;
        }
        const Vec3 h = model.moment[std::size_t(i)];
        const Mat3& I = model.inertia[std::size_t(i)];
        force[i] = model.mass[std::size_t(i)] * a + cross(wd, h) + cross(w, cross(w, h));
        torque[i] = I * wd + cross(w, I * w) + cross(h, a);
    }
    for (int i = n - 1; i >= 0; --i) {
        tau[i] = chain.prismatic[std::size_t(i)] ? force[i].z : torque[i].z;
        if (i > 0) {
            const Vec3 f = steps[i].R * force[i];
            force[i - 1] = force[i - 1] + f;
            torque[i - 1] = torque[i - 1] + steps[i].R * torque[i] + cross(steps[i].p, f);
        }
    }
}

void mass_matrix(const Dynamics& model, const double* q, double* M) {
    const Chain& chain = model.chain;
    const int n = chain.n;
    Step steps[kMaxJoints];
    for (int i = 0; i < n; ++i) steps[i] = joint_step(chain, i, q[i]);
    double m = 0.0;  // the composite body of links i..n-1, in F_i
    Vec3 h{};
    Mat3 I{};
    for (int i = n - 1; i >= 0; --i) {
        if (i == n - 1) {
            m = model.mass[std::size_t(i)];
            h = model.moment[std::size_t(i)];
            I = model.inertia[std::size_t(i)];
        } else {  // add body i to the composite of i + 1 moved into F_i
            double m_next = model.mass[std::size_t(i)];
            Vec3 h_next = model.moment[std::size_t(i)];
            Mat3 I_next = model.inertia[std::size_t(i)];
            add_moved(steps[i + 1], m, h, I, m_next, h_next, I_next);
            m = m_next;
            h = h_next;
            I = I_next;
        }
        // the composite's momentum (linear P, angular H about the origin) for a unit rate of joint i
        Vec3 P, H;
        if (chain.prismatic[std::size_t(i)]) {
            P = m * kZ;
            H = cross(h, kZ);
        } else {
            P = cross(kZ, h);
            H = I * kZ;
        }
        M[i * n + i] = chain.prismatic[std::size_t(i)] ? P.z : H.z;
        for (int j = i - 1; j >= 0; --j) {  // the same momentum seen from F_j
            P = steps[j + 1].R * P;
            H = steps[j + 1].R * H + cross(steps[j + 1].p, P);
            M[j * n + i] = M[i * n + j] = chain.prismatic[std::size_t(j)] ? P.z : H.z;
        }
    }
}

bool forward_dynamics(const Dynamics& model, const double* q, const double* qd, const double* tau, Vec3 gravity,
                      double* qdd) {
    const int n = model.chain.n;
    double M[kMaxJoints * kMaxJoints];
    mass_matrix(model, q, M);
    inverse_dynamics(model, q, qd, nullptr, gravity, qdd);
    for (int i = 0; i < n; ++i) qdd[i] = tau[i] - qdd[i];
    return cholesky_solve(M, qdd, n);
}

}  // namespace armkit
