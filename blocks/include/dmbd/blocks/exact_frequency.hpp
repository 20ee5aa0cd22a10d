#pragma once
// Frequency figures of a Zpk refined on the transfer's own response (issue 28): the
// roots of a repeated or clustered pole are scattered by rounding (the 20 computed
// roots of (s + 1)^20 lie on a circle of radius 0.16 about -1), so a crossover found on
// the roots is off by their scatter (1/(s + 1)^20: 2.15907 dB at 0.0254066 Hz instead
// of 2.15203 dB at tan(pi/20)/(2 pi) = 0.0252077 Hz). The response evaluated from the
// coefficients or the state space is not: each crossing found on the Zpk is bracketed on
// it and solved there.
#include <functional>
#include <optional>
#include <vector>

#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/zpk.hpp"

namespace dmbd::blocks {

// G(jw) (G(e^{jw ts})) from the transfer's data; empty where it cannot be evaluated
// (then the Zpk figures stand).
using ExactResponse = std::function<std::optional<Complex>(double w_rad_s)>;

// margins(loop) with every crossing moved to where the exact response crosses: ln|L| = 0
// (gain) and arg L = pi mod 2 pi (phase), by bisection on a bracket grown geometrically
// around the Zpk's crossing (up to a factor 2 in w; a crossing not bracketed there, a
// tangent one, is left as the Zpk has it); the margins then from the exact L, the phase
// margin on the branch nearest the Zpk's unwrapped phase.
Margins margins(const Zpk& loop, const ExactResponse& exact);
// bandwidth(g, drop_db) refined likewise on ln|G| - ln(|G(0)| 10^(drop_db/20)).
std::optional<double> bandwidth(const Zpk& g, const ExactResponse& exact, double drop_db = -3.0);
// bode(g, w) with the response and magnitude from `exact` where it has a value; the phase
// is its argument on the branch nearest the Zpk's (grid-independent, from DC).
Bode bode(const Zpk& g, const std::vector<double>& w_rad_s, const ExactResponse& exact);

}  // namespace dmbd::blocks
