#include "dmbd/blocks/sampled.hpp"

#include <cmath>
#include <string>

#include "dmbd/base/number_text.hpp"
#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/error.hpp"

namespace dmbd::blocks {

std::optional<int> whole_samples(double delay_s, double ts) {
  if (!(ts > 0.0) || !std::isfinite(ts)) throw InputError("a sample time must be > 0 s, got " + number_text(ts));
  if (!(delay_s >= 0.0) || !std::isfinite(delay_s))
    throw InputError("a delay must be a finite number >= 0 s, got " + number_text(delay_s));
  const double x = delay_s / ts, n = std::round(x);
  if (std::abs(x - n) > 1e-9 * std::max(1.0, n) || n > 1e6) return std::nullopt;
  return static_cast<int>(n);
}

namespace {

// e^{A t} and Gamma(t) = int_0^t e^{A s} ds B: the ZOH model over a period of t.
struct Hold {
  Matrix phi, gamma;
};
Hold hold(const StateSpace& sys, double t) {
  const StateSpace d = c2d(sys, t, C2dMethod::Zoh);
  return {d.a(), d.b()};
}

// A delay split into whole periods d and the fraction theta in [0, ts).
struct Split {
  int whole = 0;
  double theta = 0.0;
};
// Each period of delay is a state of a dense model: bounded, so that a typo cannot ask
// for gigabytes.
constexpr int kMaxDelayPeriods = 1000;

Split split(double delay_s, double ts) {
  const auto n = whole_samples(delay_s, ts);
  const double d = n ? *n : std::floor(delay_s / ts);
  if (d > kMaxDelayPeriods)
    throw InputError("a delay of " + number_text(delay_s) + " s is more than " + std::to_string(kMaxDelayPeriods) +
                     " periods of " + number_text(ts) + " s");
  return n ? Split{*n, 0.0} : Split{static_cast<int>(d), delay_s - d * ts};
}

// Rows over the columns [states (N) | inputs (m)] of the assembled model.
class Assembly {
 public:
  Assembly(int states, int inputs) : n_(states), m_(inputs) {}
  Matrix unit_state(int i) const { return unit(i); }
  Matrix unit_input(int j) const { return unit(n_ + j); }
  Matrix zero() const { return Matrix::Zero(1, n_ + m_); }

 private:
  Matrix unit(int c) const {
    Matrix r = zero();
    r(0, c) = 1.0;
    return r;
  }
  int n_, m_;
};

}  // namespace

StateSpace c2d_zoh_delayed(const StateSpace& sys, double ts, const std::vector<double>& input_delays_s,
                           const std::vector<int>& output_delay_samples) {
  if (sys.is_discrete()) throw InputError("c2d: the system is already discrete");
  const int n = sys.num_states(), m = sys.num_inputs(), p = sys.num_outputs();
  if (static_cast<int>(input_delays_s.size()) != m)
    throw InputError("c2d with delays: " + std::to_string(input_delays_s.size()) + " input delays for " +
                     std::to_string(m) + " inputs");
  std::vector<int> out_delay = output_delay_samples;
  if (out_delay.empty()) out_delay.assign(static_cast<size_t>(p), 0);
  if (static_cast<int>(out_delay.size()) != p)
    throw InputError("c2d with delays: " + std::to_string(out_delay.size()) + " output delays for " +
                     std::to_string(p) + " outputs");
  // The layout of the states: x, then u[k-d-1] per fractional input, then the registers.
  std::vector<Split> in(static_cast<size_t>(m));
  std::vector<int> frac_state(static_cast<size_t>(m), -1), in_reg(static_cast<size_t>(m), -1),
      out_reg(static_cast<size_t>(p), -1);
  int total = n;
  for (int j = 0; j < m; ++j) {
    in[static_cast<size_t>(j)] = split(input_delays_s[static_cast<size_t>(j)], ts);
    if (in[static_cast<size_t>(j)].theta > 0.0) frac_state[static_cast<size_t>(j)] = total++;
  }
  for (int j = 0; j < m; ++j)
    if (in[static_cast<size_t>(j)].whole > 0) in_reg[static_cast<size_t>(j)] = total, total += in[static_cast<size_t>(j)].whole;
  for (int i = 0; i < p; ++i) {
    if (out_delay[static_cast<size_t>(i)] < 0 || out_delay[static_cast<size_t>(i)] > kMaxDelayPeriods)
      throw InputError("c2d with delays: an output delay must be 0.." + std::to_string(kMaxDelayPeriods) + " periods");
    if (out_delay[static_cast<size_t>(i)] > 0) out_reg[static_cast<size_t>(i)] = total, total += out_delay[static_cast<size_t>(i)];
  }
  const Assembly as(total, m);
  Matrix rows = Matrix::Zero(total, total + m), out = Matrix::Zero(p, total + m);
  // u_d[j] = u_j[k-d]: the input itself, or the last of its register.
  Matrix ud(m, total + m), late(m, total + m);  // late[j]: what D sees at k ts
  for (int j = 0; j < m; ++j) {
    const auto s = static_cast<size_t>(j);
    ud.row(j) = in[s].whole == 0 ? as.unit_input(j) : as.unit_state(in_reg[s] + in[s].whole - 1);
    late.row(j) = in[s].theta > 0.0 ? as.unit_state(frac_state[s]) : Matrix(ud.row(j));
  }
  const Hold full = hold(sys, ts);
  for (int j = 0; j < m; ++j) {
    const auto s = static_cast<size_t>(j);
    if (in[s].theta == 0.0) {
      rows.topRows(n) += full.gamma.col(j) * ud.row(j);
      continue;
    }
    const Hold early = hold(sys, in[s].theta), rest = hold(sys, ts - in[s].theta);
    rows.topRows(n) += rest.gamma.col(j) * ud.row(j) + rest.phi * early.gamma.col(j) * as.unit_state(frac_state[s]);
    rows.row(frac_state[s]) = ud.row(j);
  }
  rows.topLeftCorner(n, n) += full.phi;
  for (int j = 0; j < m; ++j) {
    const auto s = static_cast<size_t>(j);
    for (int r = 0; r < in[s].whole; ++r)
      rows.row(in_reg[s] + r) = r == 0 ? as.unit_input(j) : as.unit_state(in_reg[s] + r - 1);
  }
  Matrix yhat = Matrix::Zero(p, total + m);
  yhat.leftCols(n) = sys.c();
  yhat += sys.d() * late;
  for (int i = 0; i < p; ++i) {
    const auto s = static_cast<size_t>(i);
    const int e = out_delay[s];
    for (int r = 0; r < e; ++r) rows.row(out_reg[s] + r) = r == 0 ? Matrix(yhat.row(i)) : as.unit_state(out_reg[s] + r - 1);
    out.row(i) = e == 0 ? Matrix(yhat.row(i)) : as.unit_state(out_reg[s] + e - 1);
  }
  return StateSpace(rows.leftCols(total), rows.rightCols(m), out.leftCols(total), out.rightCols(m), ts);
}

TransferFunction c2d_zoh_delayed(const TransferFunction& g, double ts, double delay_s) {
  if (g.is_discrete()) throw InputError("c2d: the system is already discrete");
  if (!g.is_proper()) throw InputError("c2d: an improper transfer function cannot be discretised");
  return c2d_zoh_delayed(StateSpace::from_tf(g), ts, {delay_s}).to_tf();
}

}  // namespace dmbd::blocks
