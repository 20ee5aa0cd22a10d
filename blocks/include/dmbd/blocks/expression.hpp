#pragma once
// Rational expressions in s (continuous) or z (discrete) with named parameters:
// `1/((s/wc)^2 + sqrt(2)*s/wc + 1)`. Grammar:
//   expr    := term (('+'|'-') term)*
//   term    := unary (('*'|'/') unary)*
//   unary   := ('-'|'+') unary | power
//   power   := primary ('^' unary)?            right-associative; the exponent must
//                                              evaluate to an integer when the base
//                                              contains s or z
//   primary := number | name | name '(' expr (',' expr)* ')' | '(' expr ')'
// Numbers use C notation: 12, 1.5, .5, 1e-3, 0x1F, 0x1.8p3, 017 (octal), 0b101,
// suffixes u/l/f, digit separators '. Names: parameters, the variable `s` or `z`,
// the constants `pi` and `e`. Functions (constant arguments only): sqrt, exp, log,
// log10, sin, cos, tan, abs, pow(a,b), min(a,b), max(a,b); exp(-s*T) is a delay where
// evaluate_rational allows one.
// Limits (each a located ExpressionError): nesting (parentheses, calls, signs,
// exponents) kMaxDepth levels, kMaxOperands numbers and names, and a rational result
// of degree at most kMaxDegree.
#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>

#include "dmbd/blocks/polynomial.hpp"

namespace dmbd::blocks {

// Parameter values by name (a diagram's parameters, --param NAME=VALUE overrides); the
// transparent comparator looks names up by std::string_view without a copy.
using ParameterMap = std::map<std::string, double, std::less<>>;

// A rational function num(x)/den(x) as produced by evaluating an expression.
struct Rational {
  // The numerator, ascending powers of x, as the arithmetic left it (not normalised: no
  // monic denominator, no common factor cancelled; TransferFunction normalises).
  Polynomial num, den;  // the denominator, ascending powers; never zero after evaluate_rational
  // A dead time: the function is e^{-s delay_s} num/den (seconds, >= 0). Only
  // evaluate_rational with allow_delay sets it, from factors exp(-s*T).
  double delay_s = 0.0;
  // num and den as the products of their factors as written: a product, quotient or
  // integer power keeps its operands' factors and multiplicities ((s + 1)^20 is s + 1
  // twenty times), a sum is one factor (its expanded numerator); num == expand(num_factors)
  // and den == expand(den_factors) up to rounding. What the roots are computed from.
  FactorList num_factors;
  FactorList den_factors;  // the denominator's factors, likewise
};

// A parsed rational expression (grammar above): parse once, evaluate at any parameter
// values. Cheap to copy (the syntax tree is shared and immutable).
class Expression {
 public:
  struct Node;
  // Deepest nesting of parentheses, calls, signs and exponents.
  static constexpr int kMaxDepth = 200;
  // Most numbers and names in one expression.
  static constexpr int kMaxOperands = 10000;
  // Highest degree in s or z of the evaluated numerator or denominator.
  static constexpr int kMaxDegree = 1000;

  // Throws ExpressionError (1-based column) on a syntax error or when a limit above
  // (kMaxDepth, kMaxOperands) is exceeded.
  static Expression parse(std::string_view text);

  // The source text exactly as parsed (columns in errors refer to it).
  const std::string& text() const { return text_; }
  // Parameter names the expression refers to (not functions, constants, s or z).
  std::set<std::string> parameters() const;
  // True when the variable (`s` or `z`) appears (s inside exp(), a delay, not counted).
  bool uses(char variable) const;
  // True when exp() of an expression in s (a delay exp(-s*T)) appears.
  bool has_delay() const;

  // Evaluate to a number; the expression must not contain s or z. Throws
  // ExpressionError naming the column of an unknown parameter, a misuse of s/z,
  // a division by zero or a function domain error.
  double evaluate(const ParameterMap& params = {}) const;
  // Evaluate to a rational function of `variable` ('s' or 'z'). The other variable
  // letter is an error. Powers of non-constant bases need integer exponents. Throws
  // ExpressionError as evaluate() does, and for a degree above kMaxDegree or a zero
  // denominator; InputError when `variable` is neither 's' nor 'z'.
  // With allow_delay, exp(-s*T) (T >= 0, constant; also exp(c - s*T)) is a delay factor,
  // in a discrete expression too (where z = e^{s ts}): the delays of the factors add
  // up in Rational::delay_s. A sum of terms with different delays, a delay inside
  // another function, and a net prediction (a delay left in the denominator) are
  // ExpressionErrors. Without allow_delay, exp() of an expression in s is one.
  Rational evaluate_rational(const ParameterMap& params, char variable, bool allow_delay = false) const;

 private:
  std::string text_;
  std::shared_ptr<const Node> root_;
};

}  // namespace dmbd::blocks
