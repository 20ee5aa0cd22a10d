#pragma once
// SISO transfer functions, continuous (ts == 0) or discrete (ts > 0, in z).
#include <optional>
#include <string_view>
#include <vector>

#include "dmbd/blocks/expression.hpp"
#include "dmbd/blocks/polynomial.hpp"

namespace dmbd::blocks {

// G = num/den, a ratio of real polynomials in s (continuous, ts == 0) or z (discrete,
// ts > 0 seconds), coefficients in ascending powers (Polynomial). An immutable value:
// the denominator is monic; improper ones (deg num > deg den, a PD without filter) are
// allowed here, but have no state-space realisation (StateSpace::from_tf).
class TransferFunction {
 public:
  // num/den, normalised: denominator monic (leading coefficient 1), exact leading
  // zeros stripped. Throws InputError for a zero denominator, a non-finite coefficient,
  // or a negative or non-finite sample time.
  TransferFunction(Polynomial num, Polynomial den, double ts = 0.0);
  // The constant gain `gain` (continuous, or discrete with sample time ts); the default is
  // the unit gain.
  TransferFunction(double gain = 1.0, double ts = 0.0);  // NOLINT: a constant gain converts implicitly
  // From coefficient lists, highest power first (MATLAB's tf(num, den) order), e.g.
  // {1}, {1, 2, 1} for 1/(s^2 + 2 s + 1).
  static TransferFunction from_descending(const std::vector<double>& num, const std::vector<double>& den,
                                          double ts = 0.0);
  // Parse a rational expression in s (ts == 0) or z (ts > 0). ExpressionError (with
  // column) for syntax errors, unknown parameters and the wrong variable.
  static TransferFunction parse(std::string_view expression, const ParameterMap& params = {}, double ts = 0.0);

  // The numerator polynomial in s (z), scaled by the normalisation: ascending powers.
  const Polynomial& num() const { return num_; }
  // The denominator polynomial in s (z): monic, ascending powers, never zero.
  const Polynomial& den() const { return den_; }
  // Sample time in seconds; 0 for a continuous transfer function.
  double ts() const { return ts_; }
  // ts() > 0: a function of z, evaluated on the unit circle z = e^{jw ts}.
  bool is_discrete() const { return ts_ > 0.0; }
  // The degree of the denominator: the number of poles (common roots not cancelled).
  int order() const { return den_.degree(); }
  // deg den - deg num: poles minus zeros (negative when improper; deg num is -1 for G = 0).
  int relative_degree() const { return den_.degree() - num_.degree(); }
  // deg num <= deg den: a state-space realisation exists.
  bool is_proper() const { return num_.degree() <= den_.degree(); }
  // deg num < deg den: no direct feedthrough (D = 0).
  bool is_strictly_proper() const { return num_.degree() < den_.degree(); }

  // Roots of den (of num), factor by factor when the factors are known (with_factors);
  // those at s = 0 (z = 1), exactly there (Polynomial::without_root, or a factor s,
  // z - 1), come out exactly 0 (1).
  std::vector<Complex> poles() const { return roots_of(split_den()); }
  std::vector<Complex> zeros() const { return roots_of(split_num()); }  // the same for num
  // Value at s = 0 (continuous) or z = 1 (discrete); nullopt when infinite (a pole
  // there that no zero cancels). 0/0 from a common root is resolved by cancelling it.
  std::optional<double> dc_gain() const;
  // num(x)/den(x) at a complex point x: s = jw (continuous) or z = e^{jw ts} (discrete).
  // No cancellation: a pole at x gives an infinite or NaN value.
  Complex evaluate(Complex x) const { return num_(x) / den_(x); }
  // The certified verdict (certified_stability.hpp) is "stable": every pole proven
  // strictly inside (Re s < 0, |z| < 1). False when unstable, marginal or undecided.
  bool is_stable() const;

  // The same transfer, its numerator and denominator known as products of factors (an
  // expression's factors as written, or the images of continuous poles under c2d): the
  // roots, the roots at the boundary point and the stability verdict are then taken
  // factor by factor, exactly as written. The caller promises that expand(num) and
  // expand(den) are num() and den() up to one common constant factor and rounding.
  TransferFunction with_factors(FactorList num, FactorList den) const;
  // The factors (with_factors), or the polynomial itself as one factor.
  FactorList num_factors() const { return has_factors_ ? num_f_ : FactorList{{num_, 1}}; }
  FactorList den_factors() const { return has_factors_ ? den_f_ : FactorList{{den_, 1}}; }  // likewise
  // num (den) without its roots exactly at the boundary point s = 0 (z = 1), counted in
  // `m`, and the value of the rest there, computed factor by factor (1 - 0.999999 is
  // exact, where the expanded polynomial's value at 1 would cancel).
  struct Split {
    Polynomial rest;      // num (den) / (x - x0)^m, leading coefficient unchanged
    int m = 0;            // roots exactly at x0
    double rest_at_x0 = 0.0;  // rest's value at x0, factor by factor
    FactorList factors;   // rest's factors
  };
  // The numerator split as above.
  Split split_num() const;
  Split split_den() const;  // the denominator, likewise

  // Cancel pole/zero pairs closer than tol relative to (1 + |root|). InputError naming
  // 'tol' unless tol is a finite number >= 0.
  TransferFunction minreal(double tol = 1e-7) const;

  // Interconnection (sample times must agree; InputError otherwise).
  friend TransferFunction operator*(const TransferFunction& a, const TransferFunction& b);  // series
  friend TransferFunction operator+(const TransferFunction& a, const TransferFunction& b);  // parallel
  // a - b, as a + (-b) (parallel connection with a negated branch).
  friend TransferFunction operator-(const TransferFunction& a, const TransferFunction& b);
  // a / b = a * (1/b); InputError when b is the zero transfer function.
  friend TransferFunction operator/(const TransferFunction& a, const TransferFunction& b);
  // -G (the numerator negated).
  TransferFunction operator-() const;
  // G^n for any integer n (G^0 = 1, G^-1 = den/num); InputError for a negative power of
  // the zero transfer function. Nothing is cancelled.
  TransferFunction pow(int n) const;

 private:
  std::vector<Complex> roots_of(const Split& s) const;
  Split split(const Polynomial& full, const FactorList& factors) const;
  Polynomial num_, den_;
  bool has_factors_ = false;
  FactorList num_f_, den_f_;
  double ts_ = 0.0;
};

// Closed loop of forward path g with feedback h: g / (1 - sign g h). sign = -1 is
// negative feedback. Throws InputError for an algebraic loop with 1 - sign g h == 0.
TransferFunction feedback(const TransferFunction& g, const TransferFunction& h = TransferFunction(1.0),
                          int sign = -1);

// Checks the sample times of two systems to be combined; throws InputError otherwise.
void require_same_ts(double a, double b, const char* what);

}  // namespace dmbd::blocks
