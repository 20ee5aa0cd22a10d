#include "dmbd/blocks/nyquist.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "angle_wrap.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/blocks/zpk.hpp"

namespace dmbd::blocks {

namespace {

// An open-loop pole in the s-plane, and on which side the contour passes it.
struct SPole {
  Complex s;
  bool pass_right;  // the contour passes on its right (the pole stays outside)
};

std::vector<SPole> s_plane_poles(const std::vector<Complex>& poles, double ts, Indent indent) {
  std::vector<SPole> out;
  for (const Complex& p : poles) {
    if (ts > 0.0 && std::abs(p) <= 1e-8) continue;  // z = 0 maps to s = -inf: nowhere near the contour
    const bool boundary = on_boundary(p, ts > 0.0);
    const bool unstable = ts > 0.0 ? std::abs(p) > 1.0 : p.real() > 0.0;
    out.push_back({ts > 0.0 ? std::log(p) / ts : p, boundary ? indent == Indent::Right : !unstable});
  }
  return out;
}

// indent_points frequencies across [Im p - r, Im p + r] for each pole near the axis,
// replacing those of w within r of it.
std::vector<double> with_points_around(std::vector<double> w, const std::vector<SPole>& poles, double r, int count) {
  for (const SPole& p : poles) {
    if (p.s.imag() < 0.0 || std::abs(p.s.real()) > r) continue;
    const double lo = std::max(0.0, p.s.imag() - r), hi = p.s.imag() + r;
    std::vector<double> next;
    for (double v : w)
      if (v < lo || v > hi) next.push_back(v);
    for (int k = 0; k < count; ++k) next.push_back(lo + (hi - lo) * k / std::max(1, count - 1));
    std::sort(next.begin(), next.end());
    w = next;
  }
  return w;
}

// A point of the contour moved onto the circle of radius r around the nearest pole
// when it lies inside it.
Complex indented(Complex s, const std::vector<SPole>& poles, double r) {
  const SPole* near = nullptr;
  for (const SPole& p : poles)
    if (!near || std::abs(s - p.s) < std::abs(s - near->s)) near = &p;
  if (!near || !(std::abs(s - near->s) < r)) return s;
  const double dy = (s - near->s).imag();
  const double dx = std::sqrt(std::max(0.0, r * r - dy * dy));
  return {near->s.real() + (near->pass_right ? dx : -dx), s.imag()};
}

int count_if_unstable(const std::vector<Complex>& poles, bool discrete, bool boundary_counts) {
  int n = 0;
  for (const Complex& p : poles) {
    const bool boundary = on_boundary(p, discrete);
    const bool unstable = discrete ? std::abs(p) > 1.0 : p.real() > 0.0;
    if (boundary ? boundary_counts : unstable) ++n;
  }
  return n;
}

}  // namespace

Indent parse_indent(const std::string& name) {
  if (name == "right") return Indent::Right;
  if (name == "left") return Indent::Left;
  if (name == "none") return Indent::None;
  throw InputError("indent_direction '" + name + "': expected right, left or none");
}

Nyquist nyquist(const std::function<Complex(Complex)>& loop, const std::vector<Complex>& open_loop_poles,
                const std::vector<Complex>& closed_loop_poles, const std::vector<double>& w_rad_s, double ts,
                double indent_radius, Indent indent, bool points_around_poles, int indent_points) {
  if (w_rad_s.empty()) throw InputError("omega: expected at least one frequency");
  for (size_t k = 0; k < w_rad_s.size(); ++k) {
    if (!(w_rad_s[k] >= 0.0) || !std::isfinite(w_rad_s[k]))
      throw InputError("omega: expected finite frequencies >= 0 rad/s, got " + std::to_string(w_rad_s[k]));
    if (k && !(w_rad_s[k] >= w_rad_s[k - 1])) throw InputError("omega: expected increasing frequencies");
  }
  if (!(indent_radius > 0.0) || !std::isfinite(indent_radius))
    throw InputError("indent_radius: expected a positive number, got " + std::to_string(indent_radius));
  const bool discrete = ts > 0.0;
  const std::vector<SPole> poles = indent == Indent::None ? std::vector<SPole>{} : s_plane_poles(open_loop_poles, ts, indent);
  const std::vector<double> w = points_around_poles ? with_points_around(w_rad_s, poles, indent_radius, indent_points) : w_rad_s;
  Nyquist out;
  for (double v : w) {
    const Complex s = indented(Complex(0.0, v), poles, indent_radius);
    out.contour.push_back(discrete ? std::exp(s * ts) : s);
    out.response.push_back(loop(out.contour.back()));
  }
  out.open_loop_unstable = count_if_unstable(open_loop_poles, discrete, indent == Indent::Left);
  out.closed_loop_unstable = count_if_unstable(closed_loop_poles, discrete, true);
  out.count = out.closed_loop_unstable - out.open_loop_unstable;
  double turn = 0.0;
  for (size_t k = 1; k < out.response.size(); ++k) {
    const Complex a = out.response[k - 1] + 1.0, b = out.response[k] + 1.0;
    if (std::isfinite(a.real()) && std::isfinite(a.imag()) && std::isfinite(b.real()) && std::isfinite(b.imag()))
      turn -= wrap_pi(std::arg(b) - std::arg(a));
  }
  out.curve_encirclements = turn / M_PI;
  return out;
}

std::vector<double> nyquist_frequencies(const std::vector<double>& grid, double ts, int indent_points) {
  std::vector<double> w;
  const double nyq = ts > 0.0 ? M_PI / ts : std::numeric_limits<double>::infinity();
  const double first = grid.empty() ? std::min(1.0, nyq) : std::min(grid.front(), nyq);
  for (int k = 0; k < indent_points; ++k) w.push_back(first * k / std::max(1, indent_points - 1));
  for (size_t k = 1; k < grid.size(); ++k)
    if (grid[k] < nyq) w.push_back(grid[k]);
  if (ts > 0.0 && w.back() < nyq) w.push_back(nyq);
  return w;
}

}  // namespace dmbd::blocks
