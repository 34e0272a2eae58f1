// Rigid-body dynamics of a serial chain: recursive Newton-Euler inverse dynamics, the joint-space
// mass matrix (composite rigid bodies) and forward dynamics (M qdd = tau - h by Cholesky).
//
// Body i is the link moved by joint i, in the frame right after its motion (joint frame i, the
// frame MJCF export's bodies use): F_i = F_{i-1} · L_{i-1} · M_i(q_i), F_0 the world (base) frame,
// L = Chain::between. Joint i turns about (or slides along) the z axis of F_i. Every body is
// held by its mass m, first moment h = m c and inertia about the frame origin I_o, in F_i; the
// Python layer (armkit/dynamics.py) prepares them once per chain. Gravity is a vector in F_0.
#pragma once

#include <vector>

#include "armkit/chain.hpp"
#include "armkit/vec.hpp"

namespace armkit {

struct Dynamics {
    Chain chain;
    std::vector<double> mass;      // n [kg]
    std::vector<Vec3> moment;      // n, m c [kg m] in F_i
    std::vector<Mat3> inertia;     // n, about the origin of F_i [kg m^2]
    Vec3 gravity;                  // the one-state calls' gravity [m/s^2] in F_0 (the batch calls take one)
};

// tau (n) = M(q) qdd + C(q, qd) qd - (gravity's generalized force); qd or qdd may be null (zero).
void inverse_dynamics(const Dynamics& model, const double* q, const double* qd, const double* qdd, Vec3 gravity,
                      double* tau);

// The joint-space mass matrix M (n x n, row-major, symmetric) at q.
void mass_matrix(const Dynamics& model, const double* q, double* M);

// qdd (n) from M(q) qdd = tau - h(q, qd) (h: inverse dynamics at qdd = 0). False if M is not
// positive definite (a joint that moves no mass); qdd is then unset.
bool forward_dynamics(const Dynamics& model, const double* q, const double* qd, const double* tau, Vec3 gravity,
                      double* qdd);

}  // namespace armkit
