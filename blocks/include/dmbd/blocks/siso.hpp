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

class Siso {
 public:
  // Any TF (improper ones have no realisation: step() is then an InputError).
  static Siso from_tf(const TransferFunction& g);
  // InputError unless the system has one input and one output.
  static Siso from_state_space(const SparseStateSpace& sys);

  const Zpk& zpk() const { return zpk_; }
  double ts() const { return zpk_.ts(); }
  bool is_discrete() const { return zpk_.is_discrete(); }
  // The rational function: as given, or the product of the factors when its
  // coefficients are representable in double precision.
  const std::optional<TransferFunction>& tf() const { return tf_; }
  // Every eigenvalue of the system it was made from (all of the TF's poles), and the
  // modes the transfer does not see: out of the input's reach or the output's view by
  // the structure, removed by a factor's controllability/observability rank test, or
  // cancelled against a zero (|z - p| <= kCancelTolerance |p|), or a common root of a
  // TF's numerator and denominator at s = 0 (z = 1).
  const std::vector<Complex>& modes() const { return modes_; }
  const std::vector<Complex>& hidden() const { return hidden_; }
  // Number of series factors (1 for a TF).
  int factors() const { return factors_; }
  // The states the transfer sees, balanced; empty for an improper TF.
  const std::optional<SparseStateSpace>& realisation() const { return realisation_; }

  static constexpr double kCancelTolerance = 1e-7;

  // Unit step from rest at n samples from 0 to t_end (see SparseStep), with its figures
  // when the transfer is stable (its final value is then the DC gain of zpk()).
  struct Step {
    TimeResponse response;
    StepInfo info;
  };
  Step step(double t_end, int n) const;
  // step_horizon() of the transfer's poles.
  double default_step_horizon() const;

 private:
  Zpk zpk_{0.0, 0, {}, {}};
  std::optional<TransferFunction> tf_;
  std::vector<Complex> modes_, hidden_;
  int factors_ = 1;
  std::optional<SparseStateSpace> realisation_;
};

}  // namespace dmbd::blocks
