#pragma once
// The normal form of a SISO plant and the boundary-layer (fast) subsystem of a
// disturbance observer (Shim & Jo 2007/2016; paper eq. ss_realization_1/2).
#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

// y^(rho) = psi' z + phi' x + g u,  z' = S z + G x,  x = (y, y', ..., y^(rho-1)).
// For P = g b(s)/a(s) (a, b monic, deg a = n, deg b = m, rho = n - m): a = q b + r;
// phi = -(q_0 .. q_{rho-1}), psi = -(r_0 .. r_{m-1}), S the companion matrix of b
// (its eigenvalues are the zeros of P: the zero dynamics), G = e_m e_1'.
struct NormalForm {
  int relative_degree = 0;  // rho = n - m >= 1, the length of x
  double g = 0.0;  // high-frequency gain
  // phi (rho entries): -(q_0 .. q_{rho-1}), the coefficients of q = a div b.
  Vector phi, psi;  // psi (m entries): -(r_0 .. r_{m-1}), the coefficients of r = a mod b
  // S (m x m): the companion matrix of the monic b, last row -(b_0 .. b_{m-1}).
  Matrix S, G;  // G (m x rho): e_m e_1', the output y driving the last zero-dynamics state
};

// The normal form above of a plant P = g b(s)/a(s) (continuous; the same algebra applies
// to a discrete TF in z). InputError for a zero plant or one that is not strictly proper
// (relative degree 0 or improper).
NormalForm normal_form(const TransferFunction& plant);

// The system matrix of the DOB's fast subsystem (paper, proof of the theorem):
// [[A - r B C, r B C], [-B C, A + B C]] with r = g / g_nominal and (A, B, C) the
// Q filter's realisation in the stretched time t/tau. Its characteristic polynomial is
// det(sI - A) det(sI - A + (r - 1) B C).
// InputError unless (a, b, c) is a SISO realisation: A n x n, B n x 1, C 1 x n.
Matrix dob_fast_subsystem(const Matrix& a, const Matrix& b, const Matrix& c, double g_ratio);

}  // namespace dmbd::blocks
