#pragma once
// Continuous <-> discrete conversion.
#include <string>

#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

enum class C2dMethod {
  Zoh,            // exact for piecewise-constant input: [Ad Bd; 0 I] = expm([A B; 0 0] ts)
  Tustin,         // bilinear s = (1/a)(z-1)/(z+1), a = ts/2, or tan(w ts/2)/w when pre-warped at w
  BackwardEuler,  // s = (z-1)/(ts z)
};

// "zoh", "tustin" (also "bilinear"), "backward-euler" / "euler"; InputError otherwise.
C2dMethod parse_c2d_method(const std::string& name);
const char* to_string(C2dMethod m);

// prewarp_rad_s > 0 only with Tustin: the discrete response equals the continuous one
// at that frequency. InputError for ts <= 0, an already discrete system, a pre-warp at
// or above the Nyquist frequency, or an improper TF.
StateSpace c2d(const StateSpace& sys, double ts, C2dMethod method, double prewarp_rad_s = 0.0);
// TF path: Tustin and backward Euler by polynomial substitution (an independent
// formulation of the state-space one), ZOH through the state space.
TransferFunction c2d(const TransferFunction& sys, double ts, C2dMethod method, double prewarp_rad_s = 0.0);

// Where a continuous pole s goes: e^{s ts} (ZOH), (1 + a s)/(1 - a s) (Tustin),
// 1/(1 - ts s) (backward Euler). Mapping the continuous poles is exact and far better
// conditioned than the roots of the discrete denominator when poles cluster near z = 1.
Complex c2d_pole(Complex s, double ts, C2dMethod method, double prewarp_rad_s = 0.0);

// The inverse maps: Tustin (poles at z = -1 are an InputError) and ZOH (matrix
// logarithm; poles on the negative real axis or at 0 are an InputError).
StateSpace d2c(const StateSpace& sys, C2dMethod method, double prewarp_rad_s = 0.0);
TransferFunction d2c(const TransferFunction& sys, C2dMethod method, double prewarp_rad_s = 0.0);

}  // namespace dmbd::blocks
