#pragma once
// The factor-wise phase of a transfer function (Bode::phase_deg's definition): the
// low-frequency asymptote K s^m gives m*90 deg (minus 180 when K < 0), and every other
// pole and zero adds its own phase change from DC. Private to blocks/.
#include <vector>

#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::blocks {

class PhaseModel {
 public:
  explicit PhaseModel(const TransferFunction& g);

  // The exact phase at w (rad/s), in radians: one std::arg per root.
  double phase_rad(double w) const;
  // The same at every w[k] into out[k] (resized), within 1e-5 rad per root or
  // conjugate pair (a polynomial arctangent, in a loop over the frequencies that the
  // compiler vectorises): enough to choose the branch of an exactly computed arg G,
  // whose distance to the next branch is 2 pi. NaN where a factor vanishes (a root on
  // the axis hit exactly); callers fall back to phase_rad there.
  void approx_phase_rad(const std::vector<double>& w, std::vector<double>& out) const;

 private:
  // Continuous time, s = jw. A root alone: 1 - jw/r = (1 - w Im r/|r|^2) -
  // jw Re r/|r|^2. A conjugate pair: (1 - jw/r)(1 - jw/conj r) = 1 - w^2/|r|^2 -
  // 2jw Re r/|r|^2, whose imaginary part keeps one sign, so one arctangent gives the
  // sum of the two factors' phases. sign: +1 for a zero, -1 for a pole.
  struct SRoot { double re_over_abs2, im_over_abs2, sign; };
  struct SPair { double two_re_over_abs2, inv_abs2, sign; };
  // Discrete time: arg(e^{jw ts} - r) - arg(1 - r), taken in [0, 2pi) for |r| < 1.
  struct ZRoot { double re, im, arg_at_dc, sign; bool inside; };

  void add_roots(const std::vector<Complex>& roots, double sign);
  double factor(const Complex& r, double w) const;

  bool discrete_ = false;
  double ts_ = 0.0;
  int m_ = 0;               // zeros minus poles at s = 0 (or z = 1)
  double low_rad_ = 0.0;    // the phase as w -> 0
  std::vector<Complex> zeros_, poles_;  // the other roots
  std::vector<SRoot> s_;
  std::vector<SPair> pairs_;
  std::vector<ZRoot> z_;
};

}  // namespace dmbd::blocks
