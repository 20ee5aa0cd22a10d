#include "dmbd/blocks/expression.hpp"

#include <cctype>
#include <cerrno>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <vector>

#include "dmbd/base/number_text.hpp"
#include "dmbd/blocks/error.hpp"

namespace dmbd::blocks {

// A chain `a + b - c` (or `a * b / c`) is one Sum (Product) node whose args are the
// operands and whose ops[k] / op_columns[k] are the operator before args[k] (ops[0] is
// '+' or '*'). So the tree's height is bounded by the nesting depth (kMaxDepth), not by
// the length of a chain: evaluation and the shared_ptr teardown recurse at most that deep.
struct Expression::Node {
  enum class Kind { Number, Name, Negate, Sum, Product, Pow, Call } kind;
  int column = 0;  // 1-based position of the token that produced the node
  double value = 0.0;
  std::string name;
  std::vector<std::shared_ptr<const Node>> args;
  std::string ops;
  std::vector<int> op_columns;
};

namespace {

using Node = Expression::Node;
using NodePtr = std::shared_ptr<const Node>;
using NodeMut = std::shared_ptr<Node>;

std::string quote(std::string_view s) { return "'" + std::string(s) + "'"; }

class Parser {
 public:
  explicit Parser(std::string_view text) : s_(text) {}

  NodePtr parse() {
    skip_space();
    if (pos_ >= s_.size()) fail("empty expression: expected a number, a name or '('", 1);
    NodePtr n = expr();
    skip_space();
    if (pos_ < s_.size()) {
      if (s_[pos_] == ')') fail("unmatched ')'", col());
      fail("unexpected " + quote(s_.substr(pos_, 1)) + ": expected an operator (+ - * / ^) or the end", col());
    }
    return n;
  }

 private:
  [[noreturn]] static void fail(const std::string& msg, int column) { throw ExpressionError(msg, column); }
  int col() const { return static_cast<int>(pos_) + 1; }
  void skip_space() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip_space();
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  static NodePtr make(Node::Kind k, int column, std::vector<NodePtr> args = {}) {
    auto n = std::make_shared<Node>();
    n->kind = k;
    n->column = column;
    n->args = std::move(args);
    return n;
  }

  // `first (op operand)*` as one Sum or Product node (just `first` when there is no op).
  template <class Operand>
  NodePtr chain(Node::Kind kind, const char* ops, Operand operand) {
    NodePtr first = operand();
    NodeMut n;
    for (;;) {
      skip_space();
      const int c = col();
      const char op = pos_ < s_.size() ? s_[pos_] : '\0';
      if (op == '\0' || std::strchr(ops, op) == nullptr) return n ? NodePtr(n) : first;
      ++pos_;
      if (!n) n = start_chain(kind, ops[0], std::move(first));
      n->ops.push_back(op);
      n->op_columns.push_back(c);
      n->args.push_back(operand());
    }
  }
  static NodeMut start_chain(Node::Kind kind, char op, NodePtr first) {
    auto n = std::make_shared<Node>();
    n->kind = kind;
    n->column = first->column;
    n->args.push_back(std::move(first));
    n->ops.push_back(op);
    n->op_columns.push_back(n->column);
    return n;
  }

  NodePtr expr() {
    return chain(Node::Kind::Sum, "+-", [this] { return term(); });
  }
  NodePtr term() {
    return chain(Node::Kind::Product, "*/", [this] { return unary(); });
  }

  // Every level of nesting (a parenthesis, a call, a sign, an exponent) passes here once.
  NodePtr unary() {
    skip_space();
    const int c = col();
    if (++depth_ > Expression::kMaxDepth)
      fail("nested more than " + std::to_string(Expression::kMaxDepth) +
               " levels deep (parentheses, calls, signs and exponents): simplify the expression", c);
    NodePtr n;
    if (accept('-')) {
      n = make(Node::Kind::Negate, c, {unary()});
    } else if (accept('+')) {
      n = unary();
    } else {
      n = power();
    }
    --depth_;
    return n;
  }

  NodePtr power() {
    NodePtr base = primary();
    skip_space();
    const int c = col();
    if (accept('^')) return make(Node::Kind::Pow, c, {base, unary()});
    return base;
  }

  NodePtr primary() {
    skip_space();
    const int c = col();
    if (pos_ >= s_.size()) fail("unexpected end of expression: expected a number, a name or '('", c);
    const char ch = s_[pos_];
    if (ch == '(') {
      ++pos_;
      NodePtr inner = expr();
      if (!accept(')')) {
        skip_space();
        if (pos_ >= s_.size()) fail("unexpected end of expression: expected ')' to close the '(' at column " +
                                        std::to_string(c), col());
        fail("expected ')' to close the '(' at column " + std::to_string(c) + ", found " +
                 quote(s_.substr(pos_, 1)), col());
      }
      return inner;
    }
    if (++operands_ > Expression::kMaxOperands)
      fail("more than " + std::to_string(Expression::kMaxOperands) + " numbers and names in one expression", c);
    if (std::isdigit(static_cast<unsigned char>(ch)) ||
        (ch == '.' && pos_ + 1 < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_ + 1])))) {
      auto n = std::make_shared<Node>();
      n->kind = Node::Kind::Number;
      n->column = c;
      n->value = number();
      return n;
    }
    if (std::isalpha(static_cast<unsigned char>(ch)) || ch == '_') {
      const size_t start = pos_;
      while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
      std::string name(s_.substr(start, pos_ - start));
      skip_space();
      if (pos_ < s_.size() && s_[pos_] == '(') {
        ++pos_;
        std::vector<NodePtr> args{expr()};
        while (accept(',')) args.push_back(expr());
        if (!accept(')')) {
          skip_space();
          fail("expected ')' or ',' in the call of " + quote(name) + " at column " + std::to_string(c), col());
        }
        auto n = make(Node::Kind::Call, c, std::move(args));
        std::const_pointer_cast<Node>(n)->name = name;
        return n;
      }
      auto n = make(Node::Kind::Name, c);
      std::const_pointer_cast<Node>(n)->name = name;
      return n;
    }
    if (ch == ')') fail("unexpected ')': expected a number, a name or '('", c);
    fail("unexpected " + quote(s_.substr(pos_, 1)) + ": expected a number, a name or '('", c);
  }

  // A number in C notation. Consumes the longest run of characters that can belong
  // to a numeric literal, then interprets it strictly.
  double number() {
    const int c = col();
    const size_t start = pos_;
    while (pos_ < s_.size()) {
      const char ch = s_[pos_];
      if (std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '\'') {
        ++pos_;
      } else if ((ch == '+' || ch == '-') && pos_ > start) {
        const char prev = static_cast<char>(std::tolower(static_cast<unsigned char>(s_[pos_ - 1])));
        const bool hex = s_.size() > start + 1 && s_[start] == '0' && (s_[start + 1] == 'x' || s_[start + 1] == 'X');
        if ((!hex && prev == 'e') || (hex && prev == 'p')) {
          ++pos_;
        } else {
          break;
        }
      } else {
        break;
      }
    }
    std::string tok;
    for (size_t i = start; i < pos_; ++i)
      if (s_[i] != '\'') tok.push_back(s_[i]);
    const std::string raw(s_.substr(start, pos_ - start));
    auto bad = [&](const std::string& why) -> double { fail("malformed number " + quote(raw) + ": " + why, c); };
    // Strip integer/float suffixes (u, l, ll, f in any case and order).
    std::string body = tok;
    const bool is_hex = body.size() > 1 && body[0] == '0' && (body[1] == 'x' || body[1] == 'X');
    while (!body.empty()) {
      const char last = static_cast<char>(std::tolower(static_cast<unsigned char>(body.back())));
      const bool hex_float = is_hex && body.find_first_of("pP") != std::string::npos;
      if (last == 'u' || last == 'l' || ((!is_hex || hex_float) && last == 'f')) {
        body.pop_back();
      } else {
        break;
      }
    }
    if (body.empty()) return bad("no digits");
    const bool is_bin = body.size() > 1 && body[0] == '0' && (body[1] == 'b' || body[1] == 'B');
    errno = 0;
    char* end = nullptr;
    double v = 0.0;
    if (is_bin) {
      if (body.size() == 2) return bad("no binary digits");
      v = static_cast<double>(std::strtoull(body.c_str() + 2, &end, 2));
    } else if (is_hex) {
      if (body.find_first_of(".pP") != std::string::npos) {
        if (body.find_first_of("pP") == std::string::npos) return bad("a hexadecimal floating constant needs a 'p' exponent");
        v = std::strtod(body.c_str(), &end);
      } else {
        if (body.size() == 2) return bad("no hexadecimal digits");
        v = static_cast<double>(std::strtoull(body.c_str() + 2, &end, 16));
      }
    } else if (body.size() > 1 && body[0] == '0' && body.find_first_of(".eE") == std::string::npos) {
      v = static_cast<double>(std::strtoull(body.c_str() + 1, &end, 8));  // octal, as in C
    } else {
      for (char ch : body)
        if (!(std::isdigit(static_cast<unsigned char>(ch)) || ch == '.' || ch == 'e' || ch == 'E' || ch == '+' ||
              ch == '-'))
          return bad("unexpected " + quote(std::string(1, ch)) + " (implicit multiplication is not allowed: write 2*s)");
      v = std::strtod(body.c_str(), &end);
    }
    if (end == nullptr || *end != '\0') return bad("unexpected " + quote(std::string(1, end ? *end : '?')));
    if (errno == ERANGE || !std::isfinite(v)) return bad("out of range");
    return v;
  }

  std::string_view s_;
  size_t pos_ = 0;
  int depth_ = 0;
  int operands_ = 0;
};

bool is_constant(const Rational& r) { return r.num.degree() <= 0 && r.den.degree() == 0; }
double constant_value(const Rational& r) { return r.num[0] / r.den[0]; }
// num/den, each its own single factor.
Rational whole(Polynomial num, Polynomial den, double delay_s = 0.0) {
  Rational r{std::move(num), std::move(den), delay_s, {}, {}};
  r.num_factors = {{r.num, 1}};
  r.den_factors = {{r.den, 1}};
  return r;
}
Rational constant(double v) { return whole(Polynomial::constant(v), Polynomial::constant(1.0)); }
// The factors a and b together, equal factors (exactly equal coefficients) merged.
FactorList joined(const FactorList& a, const FactorList& b, int power_b = 1) {
  FactorList out = a;
  for (const PolynomialFactor& f : b) {
    if (f.poly.degree() < 1) {
      out.push_back({f.poly.pow(f.multiplicity * power_b), 1});
      continue;
    }
    auto it = std::find_if(out.begin(), out.end(), [&f](const PolynomialFactor& g) { return g.poly == f.poly; });
    if (it != out.end()) {
      it->multiplicity += f.multiplicity * power_b;
    } else {
      out.push_back({f.poly, f.multiplicity * power_b});
    }
  }
  return out;
}
// Each factor's multiplicity times k >= 1 (a constant factor raised to the power).
FactorList powered(const FactorList& a, int k) {
  FactorList out;
  for (const PolynomialFactor& f : a) {
    if (f.poly.degree() < 1) {
      out.push_back({f.poly.pow(f.multiplicity * k), 1});
    } else {
      out.push_back({f.poly, f.multiplicity * k});
    }
  }
  return out;
}

struct Evaluator {
  const ParameterMap& params;
  char variable;  // 's', 'z', or 0 for a plain number
  bool allow_delay = false;  // exp(-s*T) becomes a delay factor (Rational::delay_s)

  [[noreturn]] static void fail(const std::string& msg, int column) { throw ExpressionError(msg, column); }

  static bool is_variable_name(const std::string& n) { return n == "s" || n == "z"; }

  // Checked before a product is formed, so that a long chain cannot build huge polynomials.
  void check_degree(int degree, int column) const {
    if (degree > Expression::kMaxDegree)
      fail("the expression reaches degree " + std::to_string(degree) + " in " + std::string(1, variable) +
               " (at most " + std::to_string(Expression::kMaxDegree) + ")",
           column);
  }
  Polynomial times(const Polynomial& a, const Polynomial& b, int column) const {
    check_degree(a.degree() + b.degree(), column);
    return a * b;
  }

  // A delay is a factor of the whole expression: the terms of a sum share it (a zero
  // term has none to share).
  static double shared_delay(const Rational& a, const Rational& b, int column) {
    if (a.num.is_zero()) return b.delay_s;
    if (b.num.is_zero() || a.delay_s == b.delay_s) return a.delay_s;
    fail("terms with different delays (exp(-s*" + number_text(a.delay_s) + ") and exp(-s*" + number_text(b.delay_s) +
             ")) are added: a delay must be a factor of the whole expression",
         column);
  }
  Rational add(const Rational& a, const Rational& b, double sign, int column) const {
    const double delay = shared_delay(a, b, column);
    if (is_constant(a) && is_constant(b)) return delayed(constant(constant_value(a) + sign * constant_value(b)), delay);
    if (a.den == b.den) {
      Rational r = whole(a.num + sign * b.num, a.den, delay);
      r.den_factors = a.den_factors;
      return r;
    }
    Rational r = whole(times(a.num, b.den, column) + sign * times(b.num, a.den, column), times(a.den, b.den, column), delay);
    r.den_factors = joined(a.den_factors, b.den_factors);
    return r;
  }
  Rational mul(const Rational& a, const Rational& b, int column) const {
    const double delay = a.delay_s + b.delay_s;
    if (is_constant(a) && is_constant(b)) return delayed(constant(constant_value(a) * constant_value(b)), delay);
    return {times(a.num, b.num, column), times(a.den, b.den, column), delay, joined(a.num_factors, b.num_factors),
            joined(a.den_factors, b.den_factors)};
  }
  Rational div(const Rational& a, const Rational& b, int column) const {
    if (b.num.is_zero()) fail("division by zero", column);
    const double delay = a.delay_s - b.delay_s;
    if (is_constant(a) && is_constant(b)) return delayed(constant(constant_value(a) / constant_value(b)), delay);
    return {times(a.num, b.den, column), times(a.den, b.num, column), delay, joined(a.num_factors, b.den_factors),
            joined(a.den_factors, b.num_factors)};
  }
  static Rational delayed(Rational r, double delay_s) {
    r.delay_s = delay_s;
    return r;
  }

  Rational eval(const Node& n) const {
    switch (n.kind) {
      case Node::Kind::Number:
        return constant(n.value);
      case Node::Kind::Name:
        return name(n);
      case Node::Kind::Negate: {
        Rational r = eval(*n.args[0]);
        r.num = -r.num;
        r.num_factors.push_back({Polynomial::constant(-1.0), 1});
        return r;
      }
      case Node::Kind::Sum:
      case Node::Kind::Product:
        return chain(n);
      case Node::Kind::Pow:
        return power(n);
      case Node::Kind::Call:
        return call(n);
    }
    fail("internal: unknown node", n.column);
  }

  Rational name(const Node& n) const {
    if (is_variable_name(n.name)) {
      if (variable == 0) fail(quote(n.name) + " appears where a number is expected", n.column);
      if (n.name[0] != variable)
        fail(quote(n.name) + " in a " + (variable == 's' ? "continuous-time expression (use s, or give a sample time for z)"
                                                          : "discrete-time expression (use z)"),
             n.column);
      return whole(Polynomial({0.0, 1.0}), Polynomial::constant(1.0));
    }
    if (auto it = params.find(n.name); it != params.end()) {
      if (!std::isfinite(it->second)) fail("parameter " + quote(n.name) + " is not finite", n.column);
      return constant(it->second);
    }
    if (n.name == "pi") return constant(M_PI);
    if (n.name == "e") return constant(M_E);
    fail("unknown parameter " + quote(n.name) + " (give it a value)", n.column);
  }

  // A Sum or Product, folded left to right as `((a op b) op c) ...`.
  Rational chain(const Node& n) const {
    Rational r = eval(*n.args[0]);
    for (size_t k = 1; k < n.args.size(); ++k) {
      const Rational b = eval(*n.args[k]);
      const int c = n.op_columns[k];
      switch (n.ops[k]) {
        case '+': r = add(r, b, 1.0, c); break;
        case '-': r = add(r, b, -1.0, c); break;
        case '*': r = mul(r, b, c); break;
        default: r = div(r, b, c); break;
      }
    }
    return r;
  }

  Rational power(const Node& n) const {
    const Rational base = eval(*n.args[0]);
    const Rational ex = eval(*n.args[1]);
    if (!is_constant(ex)) fail("the exponent must not contain " + std::string(1, variable), n.args[1]->column);
    const double e = constant_value(ex);
    if (base.delay_s != 0.0) {
      if (e != std::round(e) || std::abs(e) > 64) fail("a power of a delay needs an integer exponent", n.args[1]->column);
      Rational r = base;
      r.delay_s = 0.0;
      return delayed(power_of(r, e, n), base.delay_s * e);
    }
    return power_of(base, e, n);
  }

  Rational power_of(const Rational& base, double e, const Node& n) const {
    if (is_constant(base)) {
      const double v = std::pow(constant_value(base), e);
      if (!std::isfinite(v)) fail("power is not a finite real number", n.column);
      return constant(v);
    }
    if (e != std::round(e) || std::abs(e) > 64)
      fail("a power of an expression in " + std::string(1, variable) + " needs an integer exponent (|n| <= 64)",
           n.args[1]->column);
    const int k = static_cast<int>(e);
    check_degree(std::max(base.num.degree(), base.den.degree()) * std::abs(k), n.column);
    if (k == 0) return constant(1.0);
    if (k > 0) return {base.num.pow(k), base.den.pow(k), 0.0, powered(base.num_factors, k), powered(base.den_factors, k)};
    if (base.num.is_zero()) fail("division by zero", n.column);
    return {base.den.pow(-k), base.num.pow(-k), 0.0, powered(base.den_factors, -k), powered(base.num_factors, -k)};
  }

  // exp(-s*T): the delay e^{-sT} (T >= 0 seconds), with a gain e^c for exp(c - s*T).
  // The argument is always in s: in a discrete expression the caller turns T into
  // whole samples of z^-1.
  Rational delay(const Node& n) const {
    const Node& arg = *n.args[0];
    const Rational r = Evaluator{params, 's', false}.eval(arg);
    if (r.den.degree() != 0 || r.num.degree() != 1)
      fail("exp() of an expression in s must be a delay exp(-s*T) (linear in s), not " + arg_text(r), arg.column);
    const double t = -r.num[1] / r.den[0], c = r.num[0] / r.den[0];
    if (!(t >= 0.0)) fail("exp(-s*T) needs a delay T >= 0 s (exp(+s*T) is a prediction): T = " + number_text(t), arg.column);
    if (!allow_delay)
      fail("a delay exp(-s*T) is not allowed here (in a diagram, use a delay block)", n.column);
    return delayed(constant(std::exp(c)), t);
  }
  static std::string arg_text(const Rational& r) {
    return "a rational function of degree " + std::to_string(std::max(r.num.degree(), r.den.degree()));
  }
  static bool mentions_s(const Node& n) {
    if (n.kind == Node::Kind::Name && n.name == "s") return true;
    for (const auto& a : n.args)
      if (mentions_s(*a)) return true;
    return false;
  }

  Rational call(const Node& n) const {
    if (n.name == "exp" && n.args.size() == 1 && mentions_s(*n.args[0])) return delay(n);
    std::vector<double> a;
    for (const auto& arg : n.args) {
      const Rational r = eval(*arg);
      if (r.delay_s != 0.0) fail(quote(n.name) + " of a delay", arg->column);
      if (!is_constant(r))
        fail(quote(n.name) + " takes numbers only, not an expression in " + std::string(1, variable), arg->column);
      a.push_back(constant_value(r));
    }
    auto need = [&](size_t k) {
      if (a.size() != k)
        fail(quote(n.name) + " takes " + std::to_string(k) + " argument" + (k == 1 ? "" : "s") + ", got " +
                 std::to_string(a.size()),
             n.column);
    };
    static const std::map<std::string, double (*)(double)> unary = {
        {"sqrt", [](double x) { return std::sqrt(x); }},   {"exp", [](double x) { return std::exp(x); }},
        {"log", [](double x) { return std::log(x); }},     {"log10", [](double x) { return std::log10(x); }},
        {"sin", [](double x) { return std::sin(x); }},     {"cos", [](double x) { return std::cos(x); }},
        {"tan", [](double x) { return std::tan(x); }},     {"abs", [](double x) { return std::abs(x); }},
    };
    double v = 0.0;
    if (auto it = unary.find(n.name); it != unary.end()) {
      need(1);
      v = it->second(a[0]);
    } else if (n.name == "pow") {
      need(2);
      v = std::pow(a[0], a[1]);
    } else if (n.name == "min") {
      need(2);
      v = std::min(a[0], a[1]);
    } else if (n.name == "max") {
      need(2);
      v = std::max(a[0], a[1]);
    } else {
      fail("unknown function " + quote(n.name) + " (known: sqrt exp log log10 sin cos tan abs pow min max)",
           n.column);
    }
    if (!std::isfinite(v)) fail(quote(n.name) + " of its argument is not a finite real number", n.column);
    return constant(v);
  }
};

// Parameters, and whether s (outside a delay exp(-s*T)), z and a delay appear.
struct Uses {
  bool s = false, z = false, delay = false;
};

void collect(const Node& n, std::set<std::string>& out, Uses& u, bool in_exp = false) {
  if (n.kind == Node::Kind::Call && n.name == "exp") in_exp = true;
  if (n.kind == Node::Kind::Name) {
    if (n.name == "s") {
      (in_exp ? u.delay : u.s) = true;
    } else if (n.name == "z") {
      u.z = true;
    } else if (n.name != "pi" && n.name != "e") {
      out.insert(n.name);
    }
  }
  for (const auto& a : n.args) collect(*a, out, u, in_exp);
}

}  // namespace

Expression Expression::parse(std::string_view text) {
  Expression e;
  e.text_ = std::string(text);
  e.root_ = Parser(e.text_).parse();
  return e;
}

std::set<std::string> Expression::parameters() const {
  std::set<std::string> out;
  Uses u;
  if (root_) collect(*root_, out, u);
  return out;
}

bool Expression::uses(char variable) const {
  std::set<std::string> out;
  Uses u;
  if (root_) collect(*root_, out, u);
  return variable == 's' ? u.s : variable == 'z' ? u.z : false;
}

bool Expression::has_delay() const {
  std::set<std::string> out;
  Uses u;
  if (root_) collect(*root_, out, u);
  return u.delay;
}

double Expression::evaluate(const ParameterMap& params) const {
  const Rational r = Evaluator{params, 0}.eval(*root_);
  return r.num[0] / r.den[0];
}

Rational Expression::evaluate_rational(const ParameterMap& params, char variable, bool allow_delay) const {
  if (variable != 's' && variable != 'z') throw InputError("the variable of a rational expression is s or z");
  Rational r = Evaluator{params, variable, allow_delay}.eval(*root_);
  if (r.den.is_zero()) throw ExpressionError("the denominator is zero", 1);
  if (r.delay_s < 0.0)
    throw ExpressionError("the expression is a prediction exp(+s*" + number_text(-r.delay_s) +
                              "): a delay in a denominator must be cancelled by one in the numerator",
                          1);
  if (r.num.is_zero()) r.delay_s = 0.0;
  return r;
}

}  // namespace dmbd::blocks
