#pragma once
// e^{Mt} for a dense real M at any t, to rounding: long horizons (t = 1e15 time
// constants), stiff M (eigenvalues 1e12 apart) and repeated eigenvalues alike.
#include <complex>
#include <vector>

#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

// Dense complex matrices (the Schur form and its exponential).
using ComplexMatrix = Eigen::MatrixXcd;

// M = U T U* (complex Schur form, U unitary, T upper triangular) once; e^{Mt} = U e^{Tt} U*
// by scaling and squaring on T in which, at every squaring, the diagonal and the first
// superdiagonal are replaced by their exact values e^{t_ii h} and the divided
// difference of e^x (Al-Mohy and Higham, SIAM J. Matrix Anal. Appl. 31 (2009), sec. 2).
//
// For ||M t||_1 <= 1/2 the Taylor series in M's own coordinates instead (exact entry by
// entry shortly after t = 0, see taylor()).
//
// Why not Eigen's MatrixBase::exp(): its squarings amplify the rounding of a slow
// mode by 2^s when a fast mode sets the number s of squarings (1e6/((s + 1e-6)(s + 1e6))
// at t = 1e7 s: 3e-4 relative), and a long horizon compounds the rounding of
// e^{-h} over 50 squarings (1/(s + 1) at t = 5e14: 0.98 instead of 1). With the diagonal
// and superdiagonal exact at every level, those errors are gone: what is squared is only
// the coupling between modes, which a unitary T carries without amplification (an
// eigenvector basis would not: it is singular for repeated poles).
class SchurExponential {
 public:
  // Any square real M with finite entries (InputError otherwise).
  explicit SchurExponential(const Matrix& m);
  // The order of M.
  int size() const { return static_cast<int>(t_.rows()); }
  // e^{Mt} (real part; t >= 0). Entries that overflow double are inf or NaN (an unstable
  // M over a horizon it grows beyond 1e308 on).
  Matrix exp(double t) const;
  // e^{Mt} v.
  Vector apply(const Vector& v, double t) const;
  // e^{M k dt} v for k = 0 .. n-1 (columns): every kRestart-th sample (and every one with
  // ||M k dt|| <= 1/2) directly, those between by at most kRestart - 1 products with
  // e^{M dt}, so rounding cannot accumulate over the horizon.
  Matrix samples(const Vector& v, double dt, int n) const;
  // Samples between two computed directly by samples().
  static constexpr int kRestart = 16;

 private:
  ComplexMatrix triangular_exp(double t) const;  // e^{Tt}
  bool short_time(double t) const;                // ||M t||_1 <= 1/2: Taylor series
  Matrix taylor(const Matrix& v, double t) const;  // e^{Mt} v by its Taylor series
  Matrix m_;
  double norm1_ = 0.0;
  ComplexMatrix u_, t_;
};

}  // namespace dmbd::blocks
