#include "dmbd/blocks/discretize.hpp"

#include <Eigen/LU>
#include <cmath>
#include <optional>
#include <unsupported/Eigen/MatrixFunctions>

#include "dmbd/blocks/error.hpp"

namespace dmbd::blocks {

namespace {

// Tustin's a: s = (1/a)(z-1)/(z+1); a = ts/2, or tan(w ts/2)/w when pre-warped at w.
double tustin_alpha(double ts, double prewarp_rad_s) {
  if (prewarp_rad_s < 0.0 || !std::isfinite(prewarp_rad_s)) throw InputError("pre-warp frequency must be >= 0");
  if (prewarp_rad_s == 0.0) return ts / 2.0;
  if (prewarp_rad_s * ts >= M_PI)
    throw InputError("pre-warp frequency " + std::to_string(prewarp_rad_s / (2 * M_PI)) +
                     " Hz is at or above the Nyquist frequency " + std::to_string(0.5 / ts) + " Hz");
  return std::tan(prewarp_rad_s * ts / 2.0) / prewarp_rad_s;
}

void check_ts(double ts) {
  if (!(ts > 0.0) || !std::isfinite(ts)) throw InputError("sample time must be a positive number of seconds");
}

Eigen::FullPivLU<Matrix> invertible(const Matrix& m, const char* why) {
  Eigen::FullPivLU<Matrix> lu(m);
  lu.setThreshold(1e-13);
  if (!lu.isInvertible()) throw InputError(why);
  return lu;
}

// sum_k p_k * f^k * g^(n-k), used for the rational substitutions s = f/g.
Polynomial substitute(const Polynomial& p, const Polynomial& f, const Polynomial& g, int n) {
  Polynomial out;
  for (int k = 0; k <= p.degree(); ++k) out = out + p[k] * (f.pow(k) * g.pow(n - k));
  return out;
}

}  // namespace

C2dMethod parse_c2d_method(const std::string& name) {
  if (name == "zoh") return C2dMethod::Zoh;
  if (name == "tustin" || name == "bilinear") return C2dMethod::Tustin;
  if (name == "backward-euler" || name == "backward_euler" || name == "euler") return C2dMethod::BackwardEuler;
  throw InputError("unknown discretisation method '" + name + "': expected zoh, tustin or backward-euler");
}

const char* to_string(C2dMethod m) {
  switch (m) {
    case C2dMethod::Zoh: return "zoh";
    case C2dMethod::Tustin: return "tustin";
    case C2dMethod::BackwardEuler: return "backward-euler";
  }
  return "?";
}

Complex c2d_pole(Complex s, double ts, C2dMethod method, double prewarp_rad_s) {
  check_ts(ts);
  switch (method) {
    case C2dMethod::Zoh: return std::exp(s * ts);
    case C2dMethod::Tustin: {
      const double a = tustin_alpha(ts, prewarp_rad_s);
      return (1.0 + a * s) / (1.0 - a * s);
    }
    case C2dMethod::BackwardEuler: return 1.0 / (1.0 - ts * s);
  }
  return s;
}

StateSpace c2d(const StateSpace& sys, double ts, C2dMethod method, double prewarp_rad_s) {
  check_ts(ts);
  if (sys.is_discrete()) throw InputError("c2d: the system is already discrete");
  if (prewarp_rad_s != 0.0 && method != C2dMethod::Tustin) throw InputError("pre-warping applies to Tustin only");
  const int n = sys.num_states(), m = sys.num_inputs();
  const Matrix I = Matrix::Identity(n, n);
  switch (method) {
    case C2dMethod::Zoh: {
      Matrix big = Matrix::Zero(n + m, n + m);
      big.topLeftCorner(n, n) = sys.a() * ts;
      big.topRightCorner(n, m) = sys.b() * ts;
      const Matrix e = big.exp();
      return StateSpace(e.topLeftCorner(n, n), e.topRightCorner(n, m), sys.c(), sys.d(), ts);
    }
    case C2dMethod::Tustin: {
      const double a = tustin_alpha(ts, prewarp_rad_s);
      const auto lu = invertible(I - a * sys.a(), "Tustin: a pole at s = 1/a maps to z = infinity");
      const Matrix mb = lu.solve(sys.b());
      const Matrix cm = lu.inverse();  // M^-1
      return StateSpace(lu.solve(I + a * sys.a()), 2.0 * a * mb, sys.c() * cm, sys.d() + a * sys.c() * mb, ts);
    }
    case C2dMethod::BackwardEuler: {
      const auto lu = invertible(I - ts * sys.a(), "backward Euler: a pole at s = 1/ts maps to z = infinity");
      const Matrix ad = lu.inverse();
      return StateSpace(ad, ts * ad * sys.b(), sys.c() * ad, sys.d() + ts * sys.c() * ad * sys.b(), ts);
    }
  }
  throw InputError("unknown discretisation method");
}

namespace {

// The discrete denominator as the images of the continuous poles, factor by factor: a
// real pole p gives z - c2d_pole(p), a conjugate pair the real quadratic of its image
// (|w|^2 from the image itself), a pole at s = 0 the factor z - 1 exactly. The verdict
// and the poles of the result come from these (0.999999 = e^{-0.01 * 1e-4} stays a pole
// 1e-6 inside), not from the roots of the rounded z-polynomial.
FactorList image_factors(const TransferFunction& sys, double ts, C2dMethod method, double prewarp_rad_s) {
  FactorList out;
  const TransferFunction::Split d = sys.split_den();
  if (d.m > 0) out.push_back({Polynomial({-1.0, 1.0}), d.m});
  for (const PolynomialFactor& f : d.factors) {
    for (const Complex& p : f.poly.roots()) {
      if (p.imag() < 0.0) continue;
      const Complex w = c2d_pole(p, ts, method, prewarp_rad_s);
      if (p.imag() == 0.0) {
        out.push_back({Polynomial({-w.real(), 1.0}), f.multiplicity});
      } else {
        const double mag2 = method == C2dMethod::Zoh ? std::exp(2.0 * p.real() * ts) : std::norm(w);
        out.push_back({Polynomial({mag2, -2.0 * w.real(), 1.0}), f.multiplicity});
      }
    }
  }
  return out;
}

TransferFunction c2d_by_formula(const TransferFunction& sys, double ts, C2dMethod method, double prewarp_rad_s);

}  // namespace

TransferFunction c2d(const TransferFunction& sys, double ts, C2dMethod method, double prewarp_rad_s) {
  const TransferFunction g = c2d_by_formula(sys, ts, method, prewarp_rad_s);
  const FactorList den = image_factors(sys, ts, method, prewarp_rad_s);
  for (const PolynomialFactor& f : den)
    for (double c : f.poly.coeffs())
      if (!std::isfinite(c)) return g;  // a pole mapped to infinity
  if (expand(den).degree() != g.den().degree()) return g;
  const TransferFunction gd = g.with_factors({{g.num(), 1}}, den);
  // ZOH keeps the DC gain exactly; the numerator's coefficients from the matrix
  // exponential (differences of O(1) numbers at a small ts) carry it only to 1e-5 at
  // ts = 1e-7: rescaled to it. (Tustin's and backward Euler's come by substitution.)
  if (method != C2dMethod::Zoh) return gd;
  const std::optional<double> kc = sys.dc_gain(), kd = gd.dc_gain();
  if (!kc || !kd || *kc == 0.0 || *kd == 0.0 || !std::isfinite(*kc / *kd)) return gd;
  const Polynomial num = (*kc / *kd) * g.num();
  return TransferFunction(num, g.den(), ts).with_factors({{num, 1}}, den);
}

namespace {

TransferFunction c2d_by_formula(const TransferFunction& sys, double ts, C2dMethod method, double prewarp_rad_s) {
  check_ts(ts);
  if (sys.is_discrete()) throw InputError("c2d: the system is already discrete");
  if (!sys.is_proper()) throw InputError("c2d: an improper transfer function cannot be discretised");
  if (prewarp_rad_s != 0.0 && method != C2dMethod::Tustin) throw InputError("pre-warping applies to Tustin only");
  const int n = sys.order();
  switch (method) {
    case C2dMethod::Zoh:
      return c2d(StateSpace::from_tf(sys), ts, method).to_tf();
    case C2dMethod::Tustin: {
      // s = (z-1) / (a (z+1)):  multiply through by a^n (z+1)^n.
      const double a = tustin_alpha(ts, prewarp_rad_s);
      const Polynomial f({-1.0, 1.0}), g({a, a});
      return TransferFunction(substitute(sys.num(), f, g, n), substitute(sys.den(), f, g, n), ts);
    }
    case C2dMethod::BackwardEuler: {
      // s = (z-1) / (ts z):  multiply through by (ts z)^n.
      const Polynomial f({-1.0, 1.0}), g({0.0, ts});
      return TransferFunction(substitute(sys.num(), f, g, n), substitute(sys.den(), f, g, n), ts);
    }
  }
  throw InputError("unknown discretisation method");
}

}  // namespace

StateSpace d2c(const StateSpace& sys, C2dMethod method, double prewarp_rad_s) {
  if (!sys.is_discrete()) throw InputError("d2c: the system is already continuous");
  const double ts = sys.ts();
  const int n = sys.num_states(), m = sys.num_inputs();
  const Matrix I = Matrix::Identity(n, n);
  switch (method) {
    case C2dMethod::Zoh: {
      for (const Complex& p : sys.poles())
        if (std::abs(p.imag()) <= 1e-12 * std::max(1.0, std::abs(p)) && p.real() <= 0.0)
          throw InputError("d2c zoh: a pole on the negative real axis or at z = 0 has no continuous equivalent");
      Matrix big = Matrix::Zero(n + m, n + m);
      big.topLeftCorner(n, n) = sys.a();
      big.topRightCorner(n, m) = sys.b();
      big.bottomRightCorner(m, m) = Matrix::Identity(m, m);
      const Matrix l = big.log() / ts;
      return StateSpace(l.topLeftCorner(n, n), l.topRightCorner(n, m), sys.c(), sys.d(), 0.0);
    }
    case C2dMethod::Tustin: {
      const double a = tustin_alpha(ts, prewarp_rad_s);
      const auto lu = invertible(sys.a() + I, "d2c tustin: a pole at z = -1 has no continuous equivalent");
      // A = (1/a)(Ad - I)(Ad + I)^-1; Ad and (Ad+I)^-1 commute.
      const Matrix ac = lu.solve(sys.a() - I) / a;
      const Matrix mm = I - a * ac;
      const Matrix b = mm * sys.b() / (2.0 * a);
      return StateSpace(ac, b, sys.c() * mm, sys.d() - a * sys.c() * b, 0.0);
    }
    case C2dMethod::BackwardEuler: {
      const auto lu = invertible(sys.a(), "d2c backward-euler: a pole at z = 0 has no continuous equivalent");
      const Matrix mm = lu.inverse();  // M = I - ts A
      const Matrix b = mm * sys.b() / ts;
      return StateSpace((I - mm) / ts, b, sys.c() * mm, sys.d() - ts * sys.c() * b, 0.0);
    }
  }
  throw InputError("unknown discretisation method");
}

TransferFunction d2c(const TransferFunction& sys, C2dMethod method, double prewarp_rad_s) {
  if (!sys.is_discrete()) throw InputError("d2c: the system is already continuous");
  if (!sys.is_proper()) throw InputError("d2c: an improper (non-causal) transfer function");
  const int n = sys.order();
  switch (method) {
    case C2dMethod::Zoh:
      return d2c(StateSpace::from_tf(sys), method).to_tf();
    case C2dMethod::Tustin: {
      // z = (1 + a s) / (1 - a s): multiply through by (1 - a s)^n.
      const double a = tustin_alpha(sys.ts(), prewarp_rad_s);
      const Polynomial f({1.0, a}), g({1.0, -a});
      return TransferFunction(substitute(sys.num(), f, g, n), substitute(sys.den(), f, g, n), 0.0);
    }
    case C2dMethod::BackwardEuler: {
      // z = 1 / (1 - ts s): multiply through by (1 - ts s)^n.
      const Polynomial f({1.0}), g({1.0, -sys.ts()});
      return TransferFunction(substitute(sys.num(), f, g, n), substitute(sys.den(), f, g, n), 0.0);
    }
  }
  throw InputError("unknown discretisation method");
}

}  // namespace dmbd::blocks
