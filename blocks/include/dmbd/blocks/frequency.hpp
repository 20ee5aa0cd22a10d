#pragma once
// Frequency responses, margins and bandwidth. Frequencies are in rad/s.
#include <optional>
#include <vector>

#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

// A frequency response on a grid, point by point: all four vectors have one entry per
// frequency.
struct Bode {
  std::vector<double> w_rad_s;    // the frequencies, rad/s, as given
  std::vector<Complex> response;  // G(jw), or G(e^{jw ts}) when discrete
  std::vector<double> mag_db;     // 20 log10 |G| (-inf at a zero on the axis, +inf at a pole)
  // Unwrapped continuously from w = 0: the low-frequency asymptote K s^m gives
  // m*90 deg (m = zeros minus poles at s = 0, or at z = 1) minus 180 deg when K < 0;
  // every other pole and zero adds its phase change from DC, computed exactly
  // per factor (no grid-dependent unwrapping). The value at each frequency is the
  // branch of arg(response) nearest that factor phase.
  std::vector<double> phase_deg;
};

// log10-spaced points from lo to hi inclusive (n >= 2), or {lo} when n == 1.
std::vector<double> logspace(double lo, double hi, int n);
// A grid covering two decades beyond the slowest and fastest pole/zero (up to Nyquist
// for a discrete system).
std::vector<double> default_frequency_grid(const TransferFunction& sys, int n = 400);
// The same grid from roots (s-plane, or z-plane when ts > 0): two decades beyond the
// smallest and largest root magnitude (z: |log z| / ts), up to Nyquist when discrete.
std::vector<double> frequency_grid_around(const std::vector<Complex>& roots, double ts, int n);

// Direct evaluation num(jw)/den(jw) (or at z = e^{jw ts}).
std::vector<Complex> frequency_response(const TransferFunction& sys, const std::vector<double>& w_rad_s);
// All channels at every frequency via one Hessenberg reduction of A and an O(n^2)
// solve per frequency: result[k] is outputs x inputs at w[k].
std::vector<Eigen::MatrixXcd> frequency_response(const StateSpace& sys, const std::vector<double>& w_rad_s);
// Magnitude in dB and unwrapped phase in degrees (Bode::phase_deg) at w_rad_s (rad/s;
// a discrete response is periodic beyond the Nyquist frequency pi/ts); the response
// by direct evaluation, as frequency_response().
Bode bode(const TransferFunction& sys, const std::vector<double>& w_rad_s);

// One crossing of a loop transfer function.
struct Crossing {
  double w_rad_s;  // where: rad/s (0 for DC, pi/ts for Nyquist of a discrete loop)
  double margin;  // gain margin in dB (at a phase crossover) or phase margin in degrees
};

// Stability margins of a loop transfer L in negative feedback (closed loop L/(1 + L)).
struct Margins {
  // The usual convention (as MATLAB's margin): among all phase crossovers (L real
  // negative) the gain margin -20 log10 |L| of smallest magnitude, in dB. Empty where
  // there is no phase crossover.
  std::optional<double> gain_margin_db, phase_crossover_rad_s;  // rad/s, where gain_margin_db is taken
  // Among all gain crossovers (|L| = 1) the phase margin 180 + angle(L), wrapped to
  // (-180, 180], of smallest magnitude, in degrees. Empty where there is no gain crossover.
  std::optional<double> phase_margin_deg, gain_crossover_rad_s;  // rad/s, where phase_margin_deg is taken
  // Every phase crossover (margin in dB), sorted by frequency.
  std::vector<Crossing> phase_crossovers, gain_crossovers;  // every gain crossover (margin in degrees), by frequency
};

// Crossovers found exactly as roots of polynomials in w (continuous) or in the
// bilinear variable v = tan(w ts / 2) (discrete), then refined by Newton steps on
// the response itself. DC is a phase crossover only when dc_gain() is finite and
// negative (never at a pole at s = 0 or z = 1).
Margins margins(const TransferFunction& loop);

// Finishes a Margins whose crossover lists are filled: sorts each by frequency, keeps
// one of crossings within 1e-8 relative of each other (a tangent crossing is a double
// root that rounding splits in two), and takes the margins of smallest magnitude.
// Shared by margins() of a TransferFunction and of a Zpk.
void settle_margins(Margins& m);

// First frequency at which |G| falls drop_db below |G(0)| (default -3 dB, MATLAB's
// and python-control's convention). Empty when G(0) is 0 or infinite, or |G| never
// drops that far.
std::optional<double> bandwidth(const TransferFunction& sys, double drop_db = -3.0);

}  // namespace dmbd::blocks
