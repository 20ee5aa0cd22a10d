#pragma once
// Nyquist data of a loop transfer L (negative feedback): L along the Nyquist contour and
// the number of encirclements of -1 (python-control's nyquist_response).
#include <functional>
#include <string>
#include <vector>

#include "dmbd/blocks/polynomial.hpp"

namespace dmbd::blocks {

// Which side of a pole on the imaginary axis (unit circle) the contour passes: Right
// leaves it outside the contour (counted as stable), Left inside; None passes through it.
enum class Indent { Right, Left, None };
// "right", "left", "none"; InputError otherwise.
Indent parse_indent(const std::string& name);

// A loop's response along the Nyquist contour (nyquist()) and the encirclements of -1.
struct Nyquist {
  std::vector<Complex> contour;   // the points: s (continuous), z = e^{s ts} (discrete)
  std::vector<Complex> response;  // L at each point
  // Clockwise encirclements of -1 by the whole closed curve, from the Nyquist criterion:
  // Z - P, Z the closed-loop poles with Re s >= 0 (|z| >= 1; those on the boundary count),
  // P the open-loop poles inside the contour (Re s > 0, |z| > 1, and those on the
  // boundary with Indent::Left). Exact: it does not depend on the frequencies.
  int count = 0;
  int open_loop_unstable = 0;    // P
  int closed_loop_unstable = 0;  // Z
  // The same count from the sampled curve, as python-control takes it: the net clockwise
  // angle of 1 + L along the points, divided by pi (the half contour from w = 0 up; its
  // mirror image doubles it). Equal to `count` when the frequencies start at 0, reach past
  // every feature of L and are dense enough; not rounded.
  double curve_encirclements = 0.0;
};

// The contour 1j w (w in rad/s, >= 0, increasing), mapped to z = e^{jw ts} when ts > 0,
// with every point within indent_radius of an open-loop pole p (in the s-plane; a
// discrete pole through log(z)/ts, poles at z = 0 left out) moved onto the circle of that
// radius around p, on the right of a stable pole and the left of an unstable one, a pole
// on the boundary as `indent` says (python-control's indentation). With
// points_around_poles, indent_points frequencies are first inserted across
// [Im p - r, Im p + r] for each such pole with Im p >= 0 (python-control does this when it
// chose the frequencies itself). `loop` evaluates L at a point of the s- (z-) plane;
// `open_loop_poles` and `closed_loop_poles` are those of L and of L/(1 + L), in s (z).
// InputError for an empty or decreasing w, a negative frequency, or indent_radius <= 0.
Nyquist nyquist(const std::function<Complex(Complex)>& loop, const std::vector<Complex>& open_loop_poles,
                const std::vector<Complex>& closed_loop_poles, const std::vector<double>& w_rad_s, double ts,
                double indent_radius = 1e-4, Indent indent = Indent::Right, bool points_around_poles = false,
                int indent_points = 50);

// Frequencies python-control's way when none are given: `grid` (increasing, > 0) with
// indent_points equally spaced from 0 up to its first entry in front, and pi/ts at the
// end when discrete (the grid cut there).
std::vector<double> nyquist_frequencies(const std::vector<double>& grid, double ts, int indent_points = 50);

}  // namespace dmbd::blocks
