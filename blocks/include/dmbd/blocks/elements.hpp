#pragma once
// The LTI block elements the paper uses (eq. frc_ctrl and Fig. 3).
#include <optional>

#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::blocks {

// The static gain k (continuous).
TransferFunction gain_block(double k);
// PD  P + D s, or with a derivative filter P + D s / (tau_d s + 1) when tau_d > 0
// (seconds). Without the filter and with d != 0 it is improper (no state-space
// realisation). InputError for tau_d < 0.
TransferFunction pd(double p, double d, double tau_d = 0.0);
// PID with filtered derivative  P + I/s + D s / (tau_d s + 1); tau_d > 0 required
// when d != 0 so that the block is proper (InputError otherwise, and for tau_d < 0).
// The denominator is always s (tau_d s + 1): with i == 0 the numerator shares the root
// s = 0, not cancelled (minreal() removes it).
TransferFunction pid(double p, double i, double d, double tau_d);
// The same law with states by structure: P, plus I/s when `i` is given, plus
// D s/(tau_d s + 1) when `d` is given. An absent term carries no state; a given one
// keeps its state at any value (0 included: P + 0/s still has its pole at s = 0), so
// the realisation's shape does not depend on a gain's value. InputError when `d` is
// given and tau_d is not > 0.
TransferFunction pid_terms(double p, std::optional<double> i, std::optional<double> d, double tau_d);
// Butterworth low-pass of order n with -3.01 dB at cutoff_rad_s and unit DC gain:
// poles on a circle of radius wc at angles pi/2 + (2k+1) pi/(2n). InputError unless
// 1 <= order <= 20 and cutoff_rad_s > 0 (rad/s, not Hz).
TransferFunction butterworth_lowpass(int order, double cutoff_rad_s);
// k / s (continuous; a diagram's discrete integrator is k ts/(z - 1)).
TransferFunction integrator(double k = 1.0);

}  // namespace dmbd::blocks
