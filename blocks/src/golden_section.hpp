#pragma once
// Internal to blocks/: golden-section search for the minimum of a locally unimodal
// function on an interval (used for a step response's peak and the stability margin's
// minimum of |1 + L|). Written out: the search is a dozen lines and Eigen has none.
#include <cmath>
#include <functional>

namespace dmbd::blocks {

// The final bracket of the search: the minimum lies in [a, b]; c < d are the last two
// interior points and fc, fd the values there.
struct GoldenBracket {
  double a, b, c, d, fc, fd;
  double best() const { return fc <= fd ? c : d; }  // the better of the two points evaluated last
};

// Shrinks [a, b] around a minimum of f until b - a <= rel_tol |b| or after max_iter steps.
inline GoldenBracket golden_section(const std::function<double(double)>& f, double a, double b, double rel_tol, int max_iter) {
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  double c = b - r * (b - a), d = a + r * (b - a);
  double fc = f(c), fd = f(d);
  for (int it = 0; it < max_iter && b - a > rel_tol * std::abs(b); ++it) {
    if (fc <= fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - r * (b - a);
      fc = f(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + r * (b - a);
      fd = f(d);
    }
  }
  return {a, b, c, d, fc, fd};
}

}  // namespace dmbd::blocks
