#pragma once
// Real-coefficient polynomials.
#include <complex>
#include <utility>
#include <vector>

namespace dmbd::blocks {

// The complex numbers of roots, poles, zeros and frequency responses.
using Complex = std::complex<double>;

// p(x) = c[0] + c[1] x + ... + c[n] x^n with real coefficients, stored in ascending
// powers; the leading coefficient is never an exact zero (the zero polynomial has no
// coefficients and degree -1).
class Polynomial {
 public:
  Polynomial() = default;
  // From coefficients in ascending powers (c[0] the constant term); exact zeros at the
  // top are stripped.
  explicit Polynomial(std::vector<double> ascending);
  // As the vector constructor: `Polynomial({1.0, 2.0})` is 1 + 2 x.
  Polynomial(std::initializer_list<double> ascending);
  // From coefficients highest power first (MATLAB's order): {1, 2} is x + 2.
  static Polynomial from_descending(const std::vector<double>& descending);
  // The constant c (the zero polynomial when c == 0).
  static Polynomial constant(double c);
  // coefficient * x^degree (degree >= 0).
  static Polynomial monomial(int degree, double coefficient = 1.0);
  // prod (x - r_i) * leading. Complex roots must come in conjugate pairs (to a relative
  // 1e-8); the result is real. Throws InputError otherwise.
  static Polynomial from_roots(const std::vector<Complex>& roots, double leading = 1.0);

  // n, the highest power; -1 for the zero polynomial.
  int degree() const { return static_cast<int>(c_.size()) - 1; }
  // No coefficients at all (degree -1).
  bool is_zero() const { return c_.empty(); }
  // The coefficient of x^k; 0 for k < 0 or k > degree().
  double operator[](int k) const { return k >= 0 && k < static_cast<int>(c_.size()) ? c_[k] : 0.0; }
  const std::vector<double>& coeffs() const { return c_; }  // ascending
  // The coefficients highest power first, as from_descending takes them.
  std::vector<double> descending() const;
  // The coefficient of x^degree() (never 0), or 0 for the zero polynomial.
  double leading() const { return c_.empty() ? 0.0 : c_.back(); }
  // Number of roots at exactly zero (trailing zero coefficients).
  int zero_roots() const;
  // Whether x0 is a root, judged against the rounding error of evaluating p there
  // (|p(x0)| <= 1e-12 sum |c_k x0^k|). A numerical convenience for placing roots (second-
  // order sections); poles, zeros and stability verdicts use exact_roots_at
  // (root_enclosure.hpp) instead, which has no tolerance.
  bool has_root_at(double x0) const;
  // p with every root at x0 (as has_root_at decides) divided out, and how many there were.
  std::pair<Polynomial, int> without_root(double x0) const;

  // p(x) by Horner's rule.
  double operator()(double x) const;
  // p(x) at a complex point (s = jw, z = e^{jw ts}), by Horner's rule.
  Complex operator()(Complex x) const;

  // p'(x); the zero polynomial for a constant.
  Polynomial derivative() const;
  // Roots: eigenvalues of the balanced companion matrix, each polished by Newton steps
  // on p that are kept only while they reduce |p|; exact zero roots come from the
  // trailing zero coefficients. Conjugate pairs are made exactly conjugate; sorted by
  // real part, then imaginary part.
  std::vector<Complex> roots() const;

  // p / leading(): leading coefficient 1 (the zero polynomial stays zero).
  Polynomial monic() const;
  // p^n, n >= 0 (p^0 = 1); InputError for n < 0.
  Polynomial pow(int n) const;
  Polynomial compose(const Polynomial& inner) const;  // p(inner(x))
  Polynomial negated_argument() const;                // p(-x)
  // Drop leading coefficients with |c| <= rel_tol * max|c|.
  Polynomial trimmed(double rel_tol) const;

  // Sum, coefficient by coefficient (exact cancellation of the top lowers the degree).
  friend Polynomial operator+(const Polynomial& a, const Polynomial& b);
  // Difference a - b.
  friend Polynomial operator-(const Polynomial& a, const Polynomial& b);
  // Product (convolution of the coefficients); zero when either factor is zero.
  friend Polynomial operator*(const Polynomial& a, const Polynomial& b);
  // Every coefficient times k (k == 0 gives the zero polynomial).
  friend Polynomial operator*(double k, const Polynomial& a);
  // -p.
  Polynomial operator-() const;
  // Exact equality of the coefficients (no tolerance).
  bool operator==(const Polynomial& o) const { return c_ == o.c_; }
  // Some coefficient differs (exactly).
  bool operator!=(const Polynomial& o) const { return c_ != o.c_; }
  // Euclidean division: a = q b + r, deg r < deg b. Throws InputError if b is zero.
  static std::pair<Polynomial, Polynomial> divide(const Polynomial& a, const Polynomial& b);

 private:
  void strip();
  std::vector<double> c_;
};

// A polynomial kept as the product of its factors as written (an expression's
// (s + 1)^20 is the factor s + 1 with multiplicity 20): the roots of each factor are the
// roots of the product, exactly, without forming (and rounding) its coefficients.
struct PolynomialFactor {
  Polynomial poly;       // the factor's coefficients (a constant factor has no roots)
  int multiplicity = 1;  // >= 1
};
// A product of factors, in the order written.
using FactorList = std::vector<PolynomialFactor>;
// The product of the factors (each raised to its multiplicity).
Polynomial expand(const FactorList& factors);

}  // namespace dmbd::blocks
