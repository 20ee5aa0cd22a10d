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
  int relative_degree = 0;
  double g = 0.0;  // high-frequency gain
  Vector phi, psi;
  Matrix S, G;
};

// InputError for a zero or improper plant.
NormalForm normal_form(const TransferFunction& plant);

// The system matrix of the DOB's fast subsystem (paper, proof of the theorem):
// [[A - r B C, r B C], [-B C, A + B C]] with r = g / g_nominal and (A, B, C) the
// Q filter's realisation in the stretched time t/tau. Its characteristic polynomial is
// det(sI - A) det(sI - A + (r - 1) B C).
Matrix dob_fast_subsystem(const Matrix& a, const Matrix& b, const Matrix& c, double g_ratio);

}  // namespace dmbd::blocks
