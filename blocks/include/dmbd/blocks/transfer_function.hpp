#pragma once
// SISO transfer functions, continuous (ts == 0) or discrete (ts > 0, in z).
#include <optional>
#include <string_view>
#include <vector>

#include "dmbd/blocks/expression.hpp"
#include "dmbd/blocks/polynomial.hpp"

namespace dmbd::blocks {

class TransferFunction {
 public:
  // num/den, normalised: denominator monic (leading coefficient 1), exact leading
  // zeros stripped. Throws InputError for a zero denominator or a negative or
  // non-finite sample time.
  TransferFunction(Polynomial num, Polynomial den, double ts = 0.0);
  TransferFunction(double gain = 1.0, double ts = 0.0);  // NOLINT: a constant gain converts implicitly
  // From coefficient lists, highest power first.
  static TransferFunction from_descending(const std::vector<double>& num, const std::vector<double>& den,
                                          double ts = 0.0);
  // Parse a rational expression in s (ts == 0) or z (ts > 0). ExpressionError (with
  // column) for syntax errors, unknown parameters and the wrong variable.
  static TransferFunction parse(std::string_view expression, const ParameterMap& params = {}, double ts = 0.0);

  const Polynomial& num() const { return num_; }
  const Polynomial& den() const { return den_; }
  double ts() const { return ts_; }
  bool is_discrete() const { return ts_ > 0.0; }
  int order() const { return den_.degree(); }
  int relative_degree() const { return den_.degree() - num_.degree(); }
  bool is_proper() const { return num_.degree() <= den_.degree(); }
  bool is_strictly_proper() const { return num_.degree() < den_.degree(); }

  // Roots of den (of num); those at s = 0 (z = 1), as Polynomial::without_root decides
  // them, come out exactly 0 (1).
  std::vector<Complex> poles() const { return roots_of(den_); }
  std::vector<Complex> zeros() const { return roots_of(num_); }
  // Value at s = 0 (continuous) or z = 1 (discrete); nullopt when infinite (a pole
  // there that no zero cancels). 0/0 from a common root is resolved by cancelling it.
  std::optional<double> dc_gain() const;
  Complex evaluate(Complex x) const { return num_(x) / den_(x); }
  // Continuous: all poles with Re < 0. Discrete: all poles with |z| < 1.
  bool is_stable() const;

  // Cancel pole/zero pairs closer than tol relative to (1 + |root|).
  TransferFunction minreal(double tol = 1e-7) const;

  // Interconnection (sample times must agree; InputError otherwise).
  friend TransferFunction operator*(const TransferFunction& a, const TransferFunction& b);  // series
  friend TransferFunction operator+(const TransferFunction& a, const TransferFunction& b);  // parallel
  friend TransferFunction operator-(const TransferFunction& a, const TransferFunction& b);
  friend TransferFunction operator/(const TransferFunction& a, const TransferFunction& b);
  TransferFunction operator-() const;
  TransferFunction pow(int n) const;

 private:
  std::vector<Complex> roots_of(const Polynomial& p) const;
  Polynomial num_, den_;
  double ts_ = 0.0;
};

// Closed loop of forward path g with feedback h: g / (1 - sign g h). sign = -1 is
// negative feedback. Throws InputError for an algebraic loop with 1 - sign g h == 0.
TransferFunction feedback(const TransferFunction& g, const TransferFunction& h = TransferFunction(1.0),
                          int sign = -1);

// Checks the sample times of two systems to be combined; throws InputError otherwise.
void require_same_ts(double a, double b, const char* what);

}  // namespace dmbd::blocks
