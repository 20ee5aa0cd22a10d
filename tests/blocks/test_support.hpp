#pragma once
// Small comparison helpers shared by the dmbd_blocks tests. Every helper takes an
// explicit tolerance; callers justify it where they call.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>
#include <string>
#include <vector>

#include "dmbd/blocks/polynomial.hpp"
#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::blocks::test {

inline std::string to_text(const std::vector<double>& v) {
  std::ostringstream o;
  o.precision(17);
  o << "{";
  for (size_t k = 0; k < v.size(); ++k) o << (k ? ", " : "") << v[k];
  o << "}";
  return o.str();
}

inline std::string to_text(const std::vector<Complex>& v) {
  std::ostringstream o;
  o.precision(17);
  o << "{";
  for (size_t k = 0; k < v.size(); ++k) o << (k ? ", " : "") << v[k];
  o << "}";
  return o.str();
}

// |a - b| / |b| (|b| floored at 1e-300).
inline double rel_diff(Complex a, Complex b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

// Ascending coefficients of `got` equal `want` coefficient-wise within
// rel_tol * max_k |want_k| (a norm-wise relative bound: the natural accuracy of
// polynomial arithmetic in floating point).
inline ::testing::AssertionResult coeffs_near(const Polynomial& got, const std::vector<double>& want, double rel_tol) {
  double scale = 0.0;
  for (double w : want) scale = std::max(scale, std::abs(w));
  const size_t n = std::max(got.coeffs().size(), want.size());
  for (size_t k = 0; k < n; ++k) {
    const double g = got[static_cast<int>(k)];
    const double w = k < want.size() ? want[k] : 0.0;
    if (!(std::abs(g - w) <= rel_tol * scale)) {
      return ::testing::AssertionFailure() << "coefficient " << k << ": got " << to_text(got.coeffs()) << ", want "
                                           << to_text(want) << " (rel tol " << rel_tol << ")";
    }
  }
  return ::testing::AssertionSuccess();
}

inline ::testing::AssertionResult poly_near(const Polynomial& got, const Polynomial& want, double rel_tol) {
  return coeffs_near(got, want.coeffs(), rel_tol);
}

// Same TF: monic denominators compared coefficient-wise, numerators too, both within
// rel_tol relative to the denominator's largest coefficient.
inline ::testing::AssertionResult tf_near(const TransferFunction& got, const TransferFunction& want, double rel_tol) {
  if (got.ts() != want.ts())
    return ::testing::AssertionFailure() << "sample time " << got.ts() << " vs " << want.ts();
  if (got.den().degree() != want.den().degree())
    return ::testing::AssertionFailure() << "denominator degree " << got.den().degree() << " vs "
                                         << want.den().degree() << ": got " << to_text(got.den().coeffs())
                                         << ", want " << to_text(want.den().coeffs());
  double scale = 0.0;
  for (double c : want.den().coeffs()) scale = std::max(scale, std::abs(c));
  for (double c : want.num().coeffs()) scale = std::max(scale, std::abs(c));
  const int n = std::max({got.num().degree(), want.num().degree(), got.den().degree()});
  for (int k = 0; k <= n; ++k) {
    if (!(std::abs(got.num()[k] - want.num()[k]) <= rel_tol * scale))
      return ::testing::AssertionFailure() << "numerator coefficient " << k << ": got " << to_text(got.num().coeffs())
                                           << ", want " << to_text(want.num().coeffs());
    if (!(std::abs(got.den()[k] - want.den()[k]) <= rel_tol * scale))
      return ::testing::AssertionFailure() << "denominator coefficient " << k << ": got "
                                           << to_text(got.den().coeffs()) << ", want " << to_text(want.den().coeffs());
  }
  return ::testing::AssertionSuccess();
}

// Multiset equality of roots: each wanted root is matched to the nearest unused got
// root, |got - want| <= rel_tol * max(1, |want|).
inline ::testing::AssertionResult roots_near(const std::vector<Complex>& got, const std::vector<Complex>& want,
                                             double rel_tol) {
  if (got.size() != want.size())
    return ::testing::AssertionFailure() << "got " << got.size() << " roots " << to_text(got) << ", want "
                                         << want.size() << " " << to_text(want);
  std::vector<bool> used(got.size(), false);
  for (const Complex& w : want) {
    size_t best = got.size();
    for (size_t j = 0; j < got.size(); ++j)
      if (!used[j] && (best == got.size() || std::abs(got[j] - w) < std::abs(got[best] - w))) best = j;
    if (!(std::abs(got[best] - w) <= rel_tol * std::max(1.0, std::abs(w))))
      return ::testing::AssertionFailure() << "root " << w << " not found (nearest " << got[best] << "); got "
                                           << to_text(got) << " (rel tol " << rel_tol << ")";
    used[best] = true;
  }
  return ::testing::AssertionSuccess();
}

// Two complex values agree to rel_tol relative to |want|.
inline ::testing::AssertionResult complex_near(Complex got, Complex want, double rel_tol) {
  if (rel_diff(got, want) <= rel_tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "got " << got << ", want " << want << " (relative difference "
                                       << rel_diff(got, want) << " > " << rel_tol << ")";
}

}  // namespace dmbd::blocks::test
