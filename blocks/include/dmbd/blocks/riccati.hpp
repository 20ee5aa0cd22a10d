#pragma once
// Algebraic Riccati equations and the linear-quadratic regulators built on them
// (python-control's care/dare, lqr/dlqr; MATLAB's icare/idare, lqr/dlqr).
#include <vector>

#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

// The stabilising solution X = X' of the continuous algebraic Riccati equation
//   A'X + XA - (XB + N) R^-1 (B'X + N') + Q = 0,
// A n x n, B n x m, Q n x n symmetric, R m x m symmetric positive definite, N n x m (an
// empty N is zero). Stabilising: A - B R^-1 (B'X + N') has every eigenvalue in Re s < 0.
//
// Method: the Hamiltonian H = [Ã, -G; -Q̃, -Ã'] (Ã = A - B R^-1 N', G = B R^-1 B',
// Q̃ = Q - N R^-1 N') in complex Schur form, its n eigenvalues with Re < 0 moved first;
// their invariant subspace is span [U11; U21] and X = U21 U11^-1 (Laub's Schur method,
// 1979). Written here because Eigen has a Schur form but no Riccati solver and no
// reordering, and LAPACK/SLICOT are not dependencies of blocks/.
//
// InputError for inconsistent sizes, entries that are not finite, Q or R not symmetric
// (relative 1e-10), R not positive definite, or no stabilising solution (H with eigenvalues
// on the imaginary axis: (A, B) not stabilisable, or a mode of A on the axis that Q does
// not see).
Matrix solve_care(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n = Matrix());

// The stabilising solution X = X' of the discrete algebraic Riccati equation
//   A'XA - X - (A'XB + N)(R + B'XB)^-1 (B'XA + N') + Q = 0,
// the sizes and conditions of solve_care. Stabilising: A - B K, K = (R + B'XB)^-1 (B'XA + N'),
// has every eigenvalue in |z| < 1.
//
// Method: the symplectic pencil M - zL, M = [Ã, 0; -Q̃, I], L = [I, G; 0, Ã'], whose
// deflating subspace for |z| < 1 is span [I; X]. Its Cayley transform
// C = (M - L)^-1 (M + L) has the same invariant subspaces with z mapped to (z + 1)/(z - 1),
// the unit disc to Re < 0; C in complex Schur form with those eigenvalues first gives
// X = U21 U11^-1 as for the continuous equation. Unlike the symplectic matrix
// L^-1 M, this needs no inverse of A (a delay, a pole at z = 0, is common in discrete
// models); M - L is singular exactly when the pencil has an eigenvalue at z = 1, when
// there is no stabilising solution. Eigen has no QZ reordering, hence the transform.
// InputError as solve_care (eigenvalues on the unit circle).
Matrix solve_dare(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n = Matrix());

// A linear-quadratic regulator u = -K x.
struct LinearQuadratic {
  Matrix k;                   // the gain, m x n
  Matrix s;                   // the Riccati solution X, n x n
  std::vector<Complex> poles; // the eigenvalues of A - B K, sorted as sort_roots
};

// Minimises the integral of x'Qx + u'Ru + 2x'Nu for x' = Ax + Bu: K = R^-1 (B'S + N'),
// S = solve_care(A, B, Q, R, N). The InputErrors of solve_care.
LinearQuadratic lqr(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n = Matrix());
// Minimises the sum of x'Qx + u'Ru + 2x'Nu for x[k+1] = Ax[k] + Bu[k]:
// K = (R + B'SB)^-1 (B'SA + N'), S = solve_dare(A, B, Q, R, N). The InputErrors of solve_dare.
LinearQuadratic dlqr(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n = Matrix());

// The residual of each equation at X, relative to the size of its terms (the largest
// entry of |A'X| + |XA| + |Q| + ..., so that 1e-15 is a solution to rounding): what the
// tests judge a solution by, independently of how it was found.
double care_residual(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n,
                     const Matrix& x);
// The discrete equation's residual at X, relative in the same way.
double dare_residual(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n,
                     const Matrix& x);

}  // namespace dmbd::blocks
