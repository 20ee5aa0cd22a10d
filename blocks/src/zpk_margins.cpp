// Margins and bandwidth of a Zpk: every frequency where ln|G| or the unwrapped phase
// meets a level, found by certified isolation rather than polynomial roots (whose
// coefficients overflow beyond a few dozen poles).
//
// Each root r contributes to f' (f = ln|G| or the phase) a term whose range over an
// interval [a, b] is known: continuous, with r = x + jy and u = w - y, ln|G| gets
// +-u/(x^2 + u^2) and the phase -+x/(x^2 + u^2), whose extremes over [a, b] lie at the
// ends or at u = +-|x|, u = 0; discrete, the term's value at the midpoint +- its
// derivative bound T^2 |r|/dist^2 times (b - a)/2 (dist from r to the arc). Summed,
// they enclose f' in [L, U], and f in the band between the lines through f(a) and
// f(b) of slopes L and U. An interval whose band holds no level is dropped; one with
// L > 0 or U < 0 is monotone, and each level between f(a) and f(b) is one crossing,
// solved by safeguarded Newton; any other is halved (down to 1e-13 relative, where
// only a sign change counts: a level touched but not crossed is not a crossing). Below
// 1e-6 of the slowest root and above 1e6 of the fastest, ln|G| ~ e ln w is monotone
// and tends to +-inf when e != 0: a crossing there is bracketed by decades.
#include <algorithm>
#include <cmath>
#include <limits>

#include "dmbd/blocks/zpk.hpp"

namespace dmbd::blocks {

namespace {

constexpr double kDeg = 180.0 / M_PI;
constexpr double kDbPerNeper = 20.0 / M_LN10;

// base + k period for every integer k (period > 0), or base alone.
struct Levels {
  double base, period;
  std::vector<double> within(double lo, double hi) const {
    std::vector<double> out;
    if (!(lo <= hi)) return out;
    if (period == 0.0) {
      if (lo <= base && base <= hi) out.push_back(base);
      return out;
    }
    for (double k = std::ceil((lo - base) / period); base + k * period <= hi; k += 1.0) out.push_back(base + k * period);
    return out;
  }
  // Whether a level lies in [lo, hi], in constant time: a bound on f's band can span
  // 1e12 periods next to a root near the unit circle, where listing them ran out of
  // memory (issue 28: dmbd analyze hung on such discrete transfers).
  bool any_within(double lo, double hi) const {
    if (!(lo <= hi)) return false;
    if (period == 0.0) return lo <= base && base <= hi;
    if (!std::isfinite(lo) || !std::isfinite(hi)) return true;
    return base + std::ceil((lo - base) / period) * period <= hi;
  }
};

struct Part {
  const Zpk& g;
  bool phase;
  double operator()(double w) const {
    const Complex l = g.log_response(w);
    return phase ? l.imag() : l.real();
  }
  double slope(double w) const {
    const Complex s = g.log_slope(w);
    return phase ? s.imag() : s.real();
  }
};

// Distance from a root to the arc e^{j[aT, bT]}.
double arc_distance(const Complex& r, double a, double b, double ts) {
  const double phi = std::arg(r);
  if (a * ts <= phi && phi <= b * ts) return std::abs(std::abs(r) - 1.0);
  return std::min(std::abs(r - std::polar(1.0, a * ts)), std::abs(r - std::polar(1.0, b * ts)));
}

struct Range {
  double lo = 0.0, hi = 0.0;
  void add(double l, double h) { lo += l, hi += h; }
};

// Range over u in [ua, ub] of u/(x^2 + u^2) (phase = false) or of -x/(x^2 + u^2).
Range term_range(double x, double ua, double ub, bool phase) {
  const double inf = std::numeric_limits<double>::infinity();
  if (x == 0.0 && ua <= 0.0 && ub >= 0.0) return {-inf, inf};  // a root on the axis
  auto term = [&](double u) { return (phase ? -x : u) / (x * x + u * u); };
  Range r{std::min(term(ua), term(ub)), std::max(term(ua), term(ub))};
  for (double u : {std::abs(x), -std::abs(x), 0.0})
    if (ua < u && u < ub) r.lo = std::min(r.lo, term(u)), r.hi = std::max(r.hi, term(u));
  return r;
}

// Enclosure of f' over [a, b].
Range slope_range(const Part& f, double a, double b) {
  const Zpk& g = f.g;
  Range out;
  if (g.is_discrete()) {
    const double ts = g.ts(), c = 0.5 * (a + b);
    double d2 = 0.0;
    for (const auto* list : {&g.distinct_zeros(), &g.distinct_poles()})
      for (const Zpk::Root& r : *list)
        d2 += r.count * ts * ts * std::abs(r.value) / std::pow(arc_distance(r.value, a, b, ts), 2.0);
    if (g.m() != 0 && !f.phase) d2 += std::abs(g.m()) / std::pow(2.0 * std::sin(a * ts / 2.0) / ts, 2.0);
    const double s = f.slope(c), spread = 0.5 * d2 * (b - a);
    return {s - spread, s + spread};
  }
  if (g.m() != 0 && !f.phase) out.add(std::min(g.m() / a, g.m() / b), std::max(g.m() / a, g.m() / b));
  for (const Zpk::Root& z : g.distinct_zeros()) {
    const Range t = term_range(z.value.real(), a - z.value.imag(), b - z.value.imag(), f.phase);
    out.add(z.count * t.lo, z.count * t.hi);
  }
  for (const Zpk::Root& p : g.distinct_poles()) {
    const Range t = term_range(p.value.real(), a - p.value.imag(), b - p.value.imag(), f.phase);
    out.add(-p.count * t.hi, -p.count * t.lo);
  }
  return out;
}

// The band f stays in over [a, b], given f' in [s.lo, s.hi].
Range value_range(double a, double b, double fa, double fb, const Range& s) {
  if (s.lo >= 0.0) return {fa, fb};
  if (s.hi <= 0.0) return {fb, fa};
  // Lower: the lines fa + lo (w - a) and fb - hi (b - w) meet; upper likewise.
  const double wl = (fb - fa - s.hi * b + s.lo * a) / (s.lo - s.hi);
  const double wu = (fb - fa - s.lo * b + s.hi * a) / (s.hi - s.lo);
  return {fa + s.lo * (wl - a), fa + s.hi * (wu - a)};
}

// The crossing of `level` in [a, b], where f is monotone and f(a), f(b) straddle it.
double solve(const Part& f, double a, double b, double fa, double level) {
  double x = 0.5 * (a + b);
  const bool rising_left = fa - level < 0.0;
  for (int it = 0; it < 200 && b - a > 4.0 * std::numeric_limits<double>::epsilon() * b; ++it) {
    const double fx = f(x) - level;
    if (fx == 0.0) return x;
    if ((fx < 0.0) == rising_left) {
      a = x;
    } else {
      b = x;
    }
    double next = x - fx / f.slope(x);
    if (!(next > a && next < b)) next = 0.5 * (a + b);
    if (std::abs(next - x) <= 2.0 * std::numeric_limits<double>::epsilon() * x) return next;
    x = next;
  }
  return x;
}

// Crossings of the levels by f on [lo, hi] (see the file comment).
std::vector<double> middle_crossings(const Part& f, const Levels& lv, double lo, double hi) {
  struct Interval {
    double a, b, fa, fb;
  };
  std::vector<Interval> todo;
  const int segments = std::max(1, static_cast<int>(std::ceil(10.0 * std::log10(hi / lo))));
  const std::vector<double> grid = logspace(lo, hi, segments + 1);
  std::vector<double> fg(grid.size());
  for (size_t k = 0; k < grid.size(); ++k) fg[k] = f(grid[k]);
  for (size_t k = grid.size() - 1; k-- > 0;) todo.push_back({grid[k], grid[k + 1], fg[k], fg[k + 1]});
  std::vector<double> out;
  // A safety net, reached by none of the tests: past kMaxSplits halvings, intervals
  // are decided by sign changes alone.
  constexpr long kMaxSplits = 200000;
  long splits = 0;
  while (!todo.empty()) {
    const Interval iv = todo.back();
    todo.pop_back();
    const bool tiny = iv.b - iv.a <= 1e-13 * iv.b;
    const bool finite = std::isfinite(iv.fa) && std::isfinite(iv.fb);
    const Range s = slope_range(f, iv.a, iv.b);
    const bool bounded = std::isfinite(s.lo) && std::isfinite(s.hi);
    if (finite && bounded) {
      if (s.lo == 0.0 && s.hi == 0.0) continue;  // f constant: it crosses nothing
      const Range band = value_range(iv.a, iv.b, iv.fa, iv.fb, s);
      if (!lv.any_within(band.lo, band.hi)) continue;
    }
    const bool monotone = finite && bounded && (s.lo > 0.0 || s.hi < 0.0);
    if (monotone || tiny || ++splits > kMaxSplits) {
      if (!finite || (!monotone && !bounded)) continue;  // at a root on the path: a jump
      for (double l : lv.within(std::min(iv.fa, iv.fb), std::max(iv.fa, iv.fb)))
        if ((iv.fa - l) * (iv.fb - l) < 0.0) {
          out.push_back(tiny && !monotone ? 0.5 * (iv.a + iv.b) : solve(f, iv.a, iv.b, iv.fa, l));
        } else if (iv.fb == l && iv.fa != l) {
          out.push_back(iv.b);
        }
      continue;
    }
    const double c = 0.5 * (iv.a + iv.b), fc = f(c);
    todo.push_back({c, iv.b, fc, iv.fb});
    todo.push_back({iv.a, c, iv.fa, fc});
  }
  return out;
}

// The crossing of ln|G| = level beyond `edge` (towards 0 when down, towards infinity
// otherwise), where ln|G| ~ e ln w tends to sign(e) inf; none when e = 0.
std::optional<double> tail_crossing(const Part& f, double level, double edge, int e, bool down) {
  if (e == 0) return std::nullopt;
  const double limit_sign = (down ? -e : e) > 0 ? 1.0 : -1.0;
  const double fe = f(edge) - level;
  if (!(fe * limit_sign < 0.0)) return std::nullopt;
  double far = edge, ff = fe;
  for (int k = 0; k < 600 && ff * limit_sign < 0.0; ++k) {
    far = down ? far / 10.0 : far * 10.0;
    ff = f(far) - level;
  }
  if (ff * limit_sign < 0.0 || !std::isfinite(far) || far == 0.0) return std::nullopt;
  const double a = std::min(far, edge), b = std::max(far, edge);
  return solve(f, a, b, f(a), level);
}

// The span holding every root's frequency, widened by 10^6 each way; discrete: up to
// the Nyquist frequency.
std::pair<double, double> search_span(const Zpk& g) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (const auto* list : {&g.zeros(), &g.poles()})
    for (const Complex& r : *list) {
      const double w = g.is_discrete() ? (r == Complex(0.0) ? 0.0 : std::abs(std::log(r)) / g.ts()) : std::abs(r);
      if (w > 0.0 && std::isfinite(w)) lo = std::min(lo, w), hi = std::max(hi, w);
    }
  if (!(hi > 0.0)) lo = hi = g.is_discrete() ? 0.1 * M_PI / g.ts() : 1.0;
  lo *= 1e-6;
  hi *= 1e6;
  if (g.is_discrete()) {
    hi = M_PI / g.ts();
    lo = std::min(lo, 1e-6 * hi);
  }
  return {lo, hi};
}

// Every crossing of ln|G| = level, ascending.
std::vector<double> magnitude_crossings(const Zpk& g, double level) {
  const Part f{g, false};
  const auto [lo, hi] = search_span(g);
  std::vector<double> w = middle_crossings(f, Levels{level, 0.0}, lo, hi);
  if (auto t = tail_crossing(f, level, lo, g.m(), true)) w.push_back(*t);
  if (!g.is_discrete())
    if (auto t = tail_crossing(f, level, hi, -g.relative_degree(), false)) w.push_back(*t);
  std::sort(w.begin(), w.end());
  return w;
}

}  // namespace

Margins margins(const Zpk& loop) {
  Margins out;
  if (loop.is_zero()) return out;
  for (double w : magnitude_crossings(loop, 0.0)) {
    const double pm = std::remainder(180.0 + loop.log_response(w).imag() * kDeg, 360.0);
    out.gain_crossovers.push_back({w, pm <= -180.0 ? pm + 360.0 : pm});
  }
  const auto [lo, hi] = search_span(loop);
  for (double w : middle_crossings(Part{loop, true}, Levels{M_PI, 2.0 * M_PI}, lo, hi)) {
    const double mag = loop.log_response(w).real();
    if (std::isfinite(mag)) out.phase_crossovers.push_back({w, -mag * kDbPerNeper});
  }
  if (loop.m() == 0 && loop.k() < 0.0) out.phase_crossovers.push_back({0.0, -20.0 * std::log10(-loop.k())});
  if (loop.is_discrete()) {
    const double wn = M_PI / loop.ts();
    const Complex l = loop.log_response(wn);
    // L(-1) is real: its phase is 0 or pi to rounding, unless a root sits at z = -1
    // (then L is 0 or infinite there and the phase is off by pi/2: no crossover).
    if (std::isfinite(l.real()) && std::cos(l.imag()) < -0.5) out.phase_crossovers.push_back({wn, -l.real() * kDbPerNeper});
  }
  settle_margins(out);
  return out;
}

std::optional<double> bandwidth(const Zpk& g, double drop_db) {
  const std::optional<double> dc = g.dc_gain();
  if (!dc || *dc == 0.0) return std::nullopt;
  for (double w : magnitude_crossings(g, std::log(std::abs(*dc)) + drop_db / kDbPerNeper)) {
    if (g.is_discrete() && !(w < M_PI / g.ts())) continue;
    if (g.log_slope(w).real() < 0.0) return w;
  }
  return std::nullopt;
}

}  // namespace dmbd::blocks
