#include "dmbd/diagrams/tune.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "dmbd/blocks/time_response.hpp"
#include "dmbd/diagrams/linearize.hpp"

namespace dmbd::diagrams {

namespace b = dmbd::blocks;

ClosedLoopFigures closed_loop_figures(const Diagram& diagram, const std::string& from, const std::string& to) {
  ClosedLoopFigures f;
  const b::StateSpace ss = linearize(diagram, from, to);
  f.stable = ss.is_stable();
  if (!f.stable) return f;
  const b::StateSpace m = ss.minimal(1e-10);
  // Natural frequency from the slowest poles that no zero cancels.
  const b::TransferFunction g = m.to_tf();
  std::vector<b::Complex> poles = g.poles();
  const std::vector<b::Complex> zeros = g.zeros();
  auto to_s = [&](b::Complex p) { return diagram.is_discrete() ? std::log(p) / diagram.ts() : p; };
  std::vector<double> mags;
  for (const b::Complex& p : poles) {
    bool cancelled = false;
    for (const b::Complex& z : zeros)
      if (std::abs(z - p) <= 0.02 * std::abs(p)) cancelled = true;
    if (!cancelled) mags.push_back(std::abs(to_s(p)));
  }
  std::sort(mags.begin(), mags.end());
  if (mags.size() >= 2) {
    f.natural_frequency_rad_s = std::sqrt(mags[0] * mags[1]);
  } else if (mags.size() == 1) {
    f.natural_frequency_rad_s = mags[0];
  }
  const double horizon = b::default_step_horizon(m);
  const b::TimeResponse tr = b::step(m, horizon, 4000);
  const b::StepInfo si = b::step_info(m, tr);
  f.overshoot_pct = si.overshoot_pct.value_or(0.0);
  f.rise_time_s = si.rise_time_s.value_or(0.0);
  return f;
}

namespace {

double start_value(const DiagramSource& diagram, const b::ParameterMap& fixed, const std::string& name) {
  const auto d = diagram.evaluate(fixed);
  const auto it = d->parameters().find(name);
  if (it == d->parameters().end()) throw InputError("the diagram " + diagram.file() + " has no parameter '" + name + "'");
  return it->second > 0.0 ? it->second : 1.0;
}

// Largest x in a geometric bracket with ok(x) true, given ok(lo) and !ok(hi).
double bisect_log(const std::function<bool(double)>& ok, double lo, double hi, double rel_tol = 1e-4) {
  while (hi / lo > 1.0 + rel_tol) {
    const double mid = std::sqrt(lo * hi);
    if (ok(mid)) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

// Bracket the boundary of ok() around x0: returns {lo, hi} with ok(lo), !ok(hi).
std::pair<double, double> bracket(const std::function<bool(double)>& ok, double x0, const std::string& what) {
  double lo = x0, hi = x0;
  if (ok(x0)) {
    for (int k = 0; k < 70 && ok(hi); ++k) lo = hi, hi *= 4.0;
    if (ok(hi)) throw InputError(what + ": no limit found up to " + std::to_string(hi));
  } else {
    for (int k = 0; k < 70 && !ok(lo); ++k) hi = lo, lo /= 4.0;
    if (!ok(lo)) throw InputError(what + ": not met even at " + std::to_string(lo));
  }
  return {lo, hi};
}

// The closed loop of a tuning spec at gains (p, d), counting evaluations.
template <class Spec>
ClosedLoopFigures figures_at(const Spec& s, double p, double d, int& evaluations) {
  b::ParameterMap params = s.fixed;
  params[s.p_param] = p;
  params[s.d_param] = d;
  ++evaluations;
  return closed_loop_figures(*s.diagram->evaluate(params), s.from, s.to);
}

}  // namespace

PdTuningResult tune_pd(const PdTuning& s) {
  PdTuningResult r;
  auto figures = [&](double p, double d) { return figures_at(s, p, d, r.evaluations); };
  // 1. The derivative gain at the stability limit, with P = 0.
  auto stable_d = [&](double d) {
    b::ParameterMap params = s.fixed;
    params[s.p_param] = 0.0;
    params[s.d_param] = d;
    ++r.evaluations;
    const auto dg = s.diagram->evaluate(params);
    // With P = 0 a position loop keeps the plant's integrator at the origin: set that
    // root aside (|p| at rounding level against the largest pole) and judge the others.
    const auto poles = linearize(*dg, s.from, s.to).poles();
    double scale = 1.0;
    for (const auto& p : poles) scale = std::max(scale, std::abs(p));
    for (const auto& p : poles) {
      const b::Complex z = dg->is_discrete() ? std::log(p) / dg->ts() : p;
      if (std::abs(z) <= 1e-9 * scale) continue;
      if (!(z.real() < 0.0)) return false;
    }
    return true;
  };
  const double d0 = start_value(*s.diagram, s.fixed, s.d_param);
  const auto [dlo, dhi] = bracket(stable_d, d0, "stability limit of " + s.d_param);
  r.d_critical = bisect_log(stable_d, dlo, dhi, 1e-7);
  r.d = r.d_critical * std::pow(10.0, -s.gain_margin_db / 20.0);
  // 2. The highest P without overshoot.
  auto no_overshoot = [&](double p) {
    const ClosedLoopFigures f = figures(p, r.d);
    return f.stable && f.overshoot_pct <= s.max_overshoot_pct;
  };
  const double p0 = start_value(*s.diagram, s.fixed, s.p_param);
  const auto [plo, phi] = bracket(no_overshoot, p0, "overshoot bound with " + s.p_param);
  r.p = bisect_log(no_overshoot, plo, phi);
  r.figures = figures(r.p, r.d);
  return r;
}

PdTuningResult tune_critical(const CriticalTuning& s) {
  PdTuningResult r;
  if (!(s.natural_frequency_rad_s > 0.0)) throw InputError("tune_critical needs a target natural frequency > 0");
  auto figures = [&](double p, double d) { return figures_at(s, p, d, r.evaluations); };
  const double d0 = start_value(*s.diagram, s.fixed, s.d_param);
  // For a given P: the smallest D (most lightly damped) that keeps the overshoot bound.
  auto critical_d = [&](double p) {
    auto damped = [&](double d) {
      const ClosedLoopFigures f = figures(p, d);
      return f.stable && f.overshoot_pct <= s.max_overshoot_pct;
    };
    // Search downwards: "not damped" is the ok() side of the bracket.
    auto under = [&](double d) { return !damped(d); };
    double lo = d0, hi = d0;
    if (damped(d0)) {
      for (int k = 0; k < 70 && damped(lo); ++k) hi = lo, lo /= 4.0;
      if (damped(lo)) return lo;
    } else {
      for (int k = 0; k < 70 && !damped(hi); ++k) lo = hi, hi *= 4.0;
      if (!damped(hi)) throw InputError("no derivative gain meets the overshoot bound at " + s.p_param + " = " + std::to_string(p));
    }
    return bisect_log(under, lo, hi) * 1.0001;  // just on the damped side
  };
  auto too_slow = [&](double p) {
    const double d = critical_d(p);
    return figures(p, d).natural_frequency_rad_s < s.natural_frequency_rad_s;
  };
  const double p0 = start_value(*s.diagram, s.fixed, s.p_param);
  const auto [plo, phi] = bracket(too_slow, p0, "natural frequency target with " + s.p_param);
  r.p = bisect_log(too_slow, plo, phi, 1e-3);
  r.d = critical_d(r.p);
  r.figures = figures(r.p, r.d);
  return r;
}

}  // namespace dmbd::diagrams
