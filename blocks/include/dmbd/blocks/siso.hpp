#pragma once
// A SISO transfer ready for analysis, from a transfer function or from a state-space
// interconnection of any size: its zeros, poles and gain (Zpk), the modes it does not
// see, and a realisation for time responses.
//
// A state-space model is taken apart along its structure (siso.cpp): the states split
// into strongly connected groups, ordered so that A is block triangular; groups the
// input does not reach or the output does not see are left out; and wherever
// everything upstream of a group boundary acts downstream through one scalar signal
// (the coupling has rank one), the transfer splits into a series product there. Each
// factor is a small dense system; a chain of 1000 blocks is 1000 one-state factors.
#include <optional>
#include <vector>

#include "dmbd/blocks/sparse_state_space.hpp"
#include "dmbd/blocks/time_response.hpp"
#include "dmbd/blocks/zpk.hpp"

namespace dmbd::blocks {

// The analysis of one SISO transfer (what `dmbd analyze` reports): built once by
// from_tf or from_state_space, then read. Continuous or discrete as its source.
class Siso {
 public:
  // Any TF (improper ones have no realisation: step() is then an InputError).
  static Siso from_tf(const TransferFunction& g);
  // InputError unless the system has one input and one output.
  static Siso from_state_space(const SparseStateSpace& sys);

  // The transfer as zeros, poles and gain: only the modes it sees (hidden() taken out),
  // exact integrators at s = 0 (z = 1) counted in Zpk::m. Margins, bandwidth, Bode and
  // stability are computed on it.
  const Zpk& zpk() const { return zpk_; }
  // Sample time in seconds; 0 when continuous.
  double ts() const { return zpk_.ts(); }
  // ts() > 0.
  bool is_discrete() const { return zpk_.is_discrete(); }
  // The rational function: as given, or the product of the factors when its
  // coefficients are representable in double precision.
  const std::optional<TransferFunction>& tf() const { return tf_; }
  // Every eigenvalue of the system it was made from (all of the TF's poles), sorted:
  // internal stability is judged on these.
  const std::vector<Complex>& modes() const { return modes_; }
  // The modes the transfer does not see: out of the input's reach or the output's view by
  // the structure, removed by a factor's controllability/observability rank test, or
  // cancelled against a zero (|z - p| <= kCancelTolerance |p|), or a common root of a
  // TF's numerator and denominator at s = 0 (z = 1). From a state-space model whose
  // transfer is zero: every mode.
  const std::vector<Complex>& hidden() const { return hidden_; }
  // The transfer with its zero/pole pairs |z - p| <= rel_tol |p| cancelled (each zero
  // with its nearest pole, conjugate pairs together: Zpk::cancelled); the cancelled
  // poles join hidden(), `removed` (if given) receives them. modes() are unchanged, so
  // the internal verdict still sees them. The realisation and tf() are rebuilt from
  // the reduced transfer (none when its coefficients overflow). InputError for
  // rel_tol < 0 or not finite.
  Siso minreal(double rel_tol, std::vector<Complex>* removed = nullptr) const;
  // The stability verdict of the transfer's poles: from a transfer function, certified
  // (certified_stability: its factors and double coefficients as given, "undecided"
  // where an enclosure straddles the boundary); from a state-space model, the verdict
  // of zpk()'s poles (blocks::stability).
  Stability verdict() const { return verdict_; }
  // Number of series factors (1 for a TF).
  int factors() const { return factors_; }
  // The states the transfer sees, balanced; empty for an improper TF.
  const std::optional<SparseStateSpace>& realisation() const { return realisation_; }

  // The transfer at jw (e^{jw ts}) from the data it was made from, not from its roots:
  // from_tf, the coefficients (Horner); from_state_space, the realisation up to
  // kExactStates states (a Hessenberg solve of (jwI - A) x = b). Empty when neither
  // applies (a larger diagram, or after minreal: the factored form is then the data)
  // or the value is not finite. What margins and bandwidth are refined on
  // (exact_frequency.hpp).
  std::optional<Complex> response(double w_rad_s) const;
  // The largest realisation response() evaluates (a dense solve per frequency).
  static constexpr int kExactStates = 60;

  // Relative distance |z - p| <= kCancelTolerance |p| at which a zero cancels a pole.
  static constexpr double kCancelTolerance = 1e-7;

  // Unit step from rest at n samples from 0 to t_end (see SparseStep), with its figures
  // when the transfer is stable (its final value is then the DC gain of zpk()).
  struct Step {
    TimeResponse response;  // t (s) and y (n x 1) at the samples
    StepInfo info;          // all empty unless the transfer is stable
  };
  // InputError for an improper TF (no realisation), t_end <= 0 or n < 2 (n is ignored
  // when discrete: every sample k ts up to t_end).
  Step step(double t_end, int n) const;
  // step_horizon() of the transfer's poles.
  double default_step_horizon() const;

 private:
  Zpk zpk_{0.0, 0, {}, {}};
  std::optional<TransferFunction> tf_;
  std::vector<Complex> modes_, hidden_;
  int factors_ = 1;
  Stability verdict_ = Stability::Stable;
  std::optional<SparseStateSpace> realisation_;
  bool coefficients_are_data_ = false;  // from_tf: tf_ is what was given
  std::optional<StateSpace> dense_;     // from_state_space, small: the realisation
};

// Two formulations of the zeros and gain of a minimal SISO system whose poles (the
// eigenvalues of A, those at s = 0 or z = 1 exact) are `poles`:
// - the zeros as eigenvalues after deflating the system's zero pencil by orthogonal
//   steps (siso_zeros.cpp), the gain k from one evaluation of c (xI - A)^-1 b + d on the
//   imaginary axis (unit circle): O(n^3), no polynomial; backward stable (each zero
//   makes [A - zI, b; c, d] singular to rounding). What Siso uses.
Zpk zpk_by_deflation(const StateSpace& sys, const std::vector<Complex>& poles);
// - the numerator interpolated on a circle (StateSpace::numerator, as to_tf), then its
//   roots: O(n^4), and the roots of a polynomial lose accuracy with its degree (residuals
//   of 1e-9 at 15 states, 1e-2 at 30 on random systems). The tests' cross-check.
Zpk zpk_by_interpolation(const StateSpace& sys, const std::vector<Complex>& poles);
// The finite zeros of the SISO system, as zpk_by_deflation finds them (those within
// 1e-10 |A| of s = 0, z = 1, exact).
std::vector<Complex> deflated_zeros(const StateSpace& sys);

}  // namespace dmbd::blocks
