#pragma once
// The stability margin of a loop: the smallest distance of the Nyquist curve from -1,
// min |1 + L(jw)| = 1 / (peak of the sensitivity |S|), and where (python-control's
// stability_margins: sm and wms).
#include <functional>
#include <vector>

#include "dmbd/blocks/frequency.hpp"

namespace dmbd::blocks {

// The stability margin of a loop: the distance of its Nyquist curve from -1, and where.
struct StabilityMargin {
  double margin = 0.0;   // the smallest |1 + L| over 0 <= w (up to pi/ts when discrete)
  double w_rad_s = 0.0;  // where; +inf when the infimum is L's limit at w -> infinity
  // Every local minimum of |1 + L| (Crossing::margin is |1 + L| there), by frequency; the
  // ends 0 and pi/ts (or infinity) count when |1 + L| rises from them.
  std::vector<Crossing> minima;
};

// `loop_at(w)` is L(jw) (L(e^{jw ts}) when ts > 0), `features` the roots whose magnitudes
// (|log z| / ts when discrete) and damped frequencies set the scales to look at: L's
// poles and zeros and the closed loop's poles (a sharp minimum of |1 + L| sits at the
// damped frequency of a lightly damped closed-loop pole); `at_infinity` is L's value as
// w -> infinity (continuous; D of a realisation). |1 + L| is sampled on the grid of
// frequency_grid_around(features) with 2000 points and those frequencies added, and
// every sampled local minimum refined by golden-section search between its neighbours
// to 1e-12 relative in w (the value, flat there, to rounding). Points where L is not
// finite (a pole on the axis) are never minima.
StabilityMargin stability_margin(const std::function<Complex(double)>& loop_at, const std::vector<Complex>& features,
                                 double ts, Complex at_infinity);

}  // namespace dmbd::blocks
