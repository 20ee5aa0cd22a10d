#pragma once
// Continuous <-> discrete conversion.
#include <string>

#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

// How a continuous system becomes a discrete one with sample time ts (c2d), and back
// (d2c). The comments give the substitution for s (a the Tustin constant).
enum class C2dMethod {
  Zoh,            // exact for piecewise-constant input: [Ad Bd; 0 I] = expm([A B; 0 0] ts)
  Tustin,         // bilinear s = (1/a)(z-1)/(z+1), a = ts/2, or tan(w ts/2)/w when pre-warped at w
  BackwardEuler,  // s = (z-1)/(ts z)
};

// "zoh", "tustin" (also "bilinear"), "backward-euler" / "euler"; InputError otherwise.
C2dMethod parse_c2d_method(const std::string& name);
// The method's canonical name, as parse_c2d_method reads it: "zoh", "tustin",
// "backward-euler".
const char* to_string(C2dMethod m);

// The discrete equivalent with sample time ts (seconds). prewarp_rad_s > 0 only with
// Tustin: the discrete response equals the continuous one at that frequency. InputError
// for ts <= 0, an already discrete system, a pre-warp with another method or at or above
// the Nyquist frequency, or an improper TF; Tustin (backward Euler) also for a pole at
// s = 1/a (s = 1/ts), which maps to z = infinity.
StateSpace c2d(const StateSpace& sys, double ts, C2dMethod method, double prewarp_rad_s = 0.0);
// TF path: Tustin and backward Euler by polynomial substitution (an independent
// formulation of the state-space one), ZOH through the state space.
TransferFunction c2d(const TransferFunction& sys, double ts, C2dMethod method, double prewarp_rad_s = 0.0);

// Where a continuous pole s goes: e^{s ts} (ZOH), (1 + a s)/(1 - a s) (Tustin),
// 1/(1 - ts s) (backward Euler). Mapping the continuous poles is exact and far better
// conditioned than the roots of the discrete denominator when poles cluster near z = 1.
Complex c2d_pole(Complex s, double ts, C2dMethod method, double prewarp_rad_s = 0.0);

// The inverse maps, to a continuous model: Tustin (poles at z = -1 are an InputError),
// ZOH (matrix logarithm; poles on the negative real axis or at 0 are an InputError) and
// backward Euler (a pole at z = 0 is an InputError). The sample time is the system's
// own; InputError for a continuous system (and, for the TF, an improper one).
StateSpace d2c(const StateSpace& sys, C2dMethod method, double prewarp_rad_s = 0.0);
// The same for a transfer function: Tustin and backward Euler by polynomial substitution,
// ZOH through the state space.
TransferFunction d2c(const TransferFunction& sys, C2dMethod method, double prewarp_rad_s = 0.0);

}  // namespace dmbd::blocks
