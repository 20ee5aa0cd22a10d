#pragma once
// Real-coefficient polynomials.
#include <complex>
#include <utility>
#include <vector>

namespace dmbd::blocks {

using Complex = std::complex<double>;

// p(x) = c[0] + c[1] x + ... + c[n] x^n with real coefficients, stored in ascending
// powers; the leading coefficient is never an exact zero (the zero polynomial has no
// coefficients and degree -1).
class Polynomial {
 public:
  Polynomial() = default;
  explicit Polynomial(std::vector<double> ascending);
  Polynomial(std::initializer_list<double> ascending);
  static Polynomial from_descending(const std::vector<double>& descending);
  static Polynomial constant(double c);
  static Polynomial monomial(int degree, double coefficient = 1.0);
  // prod (x - r_i) * leading. Complex roots must come in conjugate pairs (to a relative
  // 1e-8); the result is real. Throws InputError otherwise.
  static Polynomial from_roots(const std::vector<Complex>& roots, double leading = 1.0);

  int degree() const { return static_cast<int>(c_.size()) - 1; }
  bool is_zero() const { return c_.empty(); }
  double operator[](int k) const { return k >= 0 && k < static_cast<int>(c_.size()) ? c_[k] : 0.0; }
  const std::vector<double>& coeffs() const { return c_; }  // ascending
  std::vector<double> descending() const;
  double leading() const { return c_.empty() ? 0.0 : c_.back(); }
  // Number of roots at exactly zero (trailing zero coefficients).
  int zero_roots() const;
  // Whether x0 is a root, judged against the rounding error of evaluating p there.
  bool has_root_at(double x0) const;
  // p with every root at x0 divided out, and how many there were.
  std::pair<Polynomial, int> without_root(double x0) const;

  double operator()(double x) const;
  Complex operator()(Complex x) const;

  Polynomial derivative() const;
  // Roots: eigenvalues of the balanced companion matrix, each polished by Newton steps
  // on p that are kept only while they reduce |p|; exact zero roots come from the
  // trailing zero coefficients. Conjugate pairs are made exactly conjugate; sorted by
  // real part, then imaginary part.
  std::vector<Complex> roots() const;

  Polynomial monic() const;
  Polynomial pow(int n) const;
  Polynomial compose(const Polynomial& inner) const;  // p(inner(x))
  Polynomial negated_argument() const;                // p(-x)
  // Drop leading coefficients with |c| <= rel_tol * max|c|.
  Polynomial trimmed(double rel_tol) const;

  friend Polynomial operator+(const Polynomial& a, const Polynomial& b);
  friend Polynomial operator-(const Polynomial& a, const Polynomial& b);
  friend Polynomial operator*(const Polynomial& a, const Polynomial& b);
  friend Polynomial operator*(double k, const Polynomial& a);
  Polynomial operator-() const;
  bool operator==(const Polynomial& o) const { return c_ == o.c_; }
  bool operator!=(const Polynomial& o) const { return c_ != o.c_; }
  // Euclidean division: a = q b + r, deg r < deg b. Throws InputError if b is zero.
  static std::pair<Polynomial, Polynomial> divide(const Polynomial& a, const Polynomial& b);

 private:
  void strip();
  std::vector<double> c_;
};

}  // namespace dmbd::blocks
