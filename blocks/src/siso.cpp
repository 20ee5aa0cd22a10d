// The series factorisation of a SISO state-space model (see siso.hpp).
//
// Order the kept states group by group (A block lower triangular) and cut between two
// groups: U the states before the cut, W those after. With K = [A_WU B_W; C_U D] (rows:
// W and the output; columns: U and the input), rank K <= 1 means K = beta gamma': the
// upstream part acts downstream only through the scalar v = gamma' [x_U; u]. Between
// two such cuts p < q, the states S in between form the factor
//   v_q = (c_S (sI - A_SS)^-1 b_S + lambda) v_p,
// with b_S = beta_p on S, c_S = gamma_q on S, and lambda from gamma_q = lambda gamma_p on
// U_p and the input (the rows of W_q are rows of W_p, so both are multiples of gamma_p).
// The first cut (before every state) has v_0 = gamma_0 u; the last (after every state)
// has v = y. So G = gamma_0 prod(factors): exact, and each factor small.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "dmbd/blocks/certified_stability.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/siso.hpp"

namespace dmbd::blocks {

namespace {

using Entries = std::vector<std::pair<int, double>>;  // (column, value), sorted; column -1 is the input
constexpr double kRankOneTolerance = 1e-10;

// The states' groups that the input reaches and the output sees.
std::vector<bool> relevant_groups(const SparseStateSpace& sys, const std::vector<std::vector<int>>& groups) {
  const size_t ng = groups.size();
  std::vector<size_t> group_of(static_cast<size_t>(sys.num_states()));
  for (size_t g = 0; g < ng; ++g)
    for (int i : groups[g]) group_of[static_cast<size_t>(i)] = g;
  std::vector<std::vector<size_t>> users(ng);
  std::vector<bool> reached(ng, false), seen(ng, false);
  for (size_t g = 0; g < ng; ++g)
    for (int i : groups[g]) {
      for (SparseMatrix::InnerIterator it(sys.a(), i); it; ++it) {
        const size_t h = group_of[static_cast<size_t>(it.col())];
        if (h == g || it.value() == 0.0) continue;
        users[h].push_back(g);
        reached[g] = reached[g] || reached[h];  // h comes before g
      }
      for (SparseMatrix::InnerIterator it(sys.b(), i); it; ++it) reached[g] = reached[g] || it.value() != 0.0;
    }
  for (SparseMatrix::InnerIterator it(sys.c(), 0); it; ++it)
    if (it.value() != 0.0) seen[group_of[static_cast<size_t>(it.col())]] = true;
  for (size_t g = ng; g-- > 0;)
    for (size_t u : users[g]) seen[g] = seen[g] || seen[u];
  std::vector<bool> keep(ng);
  for (size_t g = 0; g < ng; ++g) keep[g] = reached[g] && seen[g];
  return keep;
}

double value_at(const Entries& v, int col) {
  const auto it = std::lower_bound(v.begin(), v.end(), std::make_pair(col, -std::numeric_limits<double>::infinity()));
  return it != v.end() && it->first == col ? it->second : 0.0;
}

double inf_norm(const Entries& v) {
  double m = 0.0;
  for (const auto& e : v) m = std::max(m, std::abs(e.second));
  return m;
}

// Whether v = alpha ref to rounding, alpha read at ref's largest entry `pivot`.
bool proportional(const Entries& v, const Entries& ref, int pivot, double& alpha) {
  alpha = value_at(v, pivot) / value_at(ref, pivot);
  const double tol = kRankOneTolerance * std::max(inf_norm(v), std::abs(alpha) * inf_norm(ref));
  size_t i = 0, j = 0;
  while (i < v.size() || j < ref.size()) {
    const int cv = i < v.size() ? v[i].first : std::numeric_limits<int>::max(), cr = j < ref.size() ? ref[j].first : std::numeric_limits<int>::max();
    const double x = cv <= cr ? v[i].second : 0.0, y = cr <= cv ? ref[j].second : 0.0;
    if (std::abs(x - alpha * y) > tol) return false;
    i += cv <= cr ? 1 : 0;
    j += cr <= cv ? 1 : 0;
  }
  return true;
}

// The kept system with its states in group order: A, the input column b, the output
// row c (as entries), d.
struct Chain {
  SparseMatrix a;
  Vector b;
  Entries c;
  double d;
  std::vector<int> starts;  // first state of each group, then the number of states
  double ts;
};

struct Cut {
  int s;          // first state after the cut
  Entries gamma;  // v = gamma' [x_0 .. x_{s-1}; u]
  Entries beta;   // (row >= s, coefficient): that row's coupling is coefficient * gamma
};

// Row i's entries in columns < s, after the input's.
Entries coupling_row(const Chain& ch, int i, int s) {
  Entries v;
  if (ch.b(i) != 0.0) v.emplace_back(-1, ch.b(i));
  for (SparseMatrix::InnerIterator it(ch.a, i); it && it.col() < s; ++it)
    if (it.value() != 0.0) v.emplace_back(static_cast<int>(it.col()), it.value());
  return v;
}

// The cut before state s if the coupling across it has rank <= 1; `rows` are the rows
// >= s with an entry in columns < s or in b.
std::optional<Cut> cut_at(const Chain& ch, int s, const std::vector<int>& rows) {
  std::vector<Entries> vs;
  for (int i : rows) vs.push_back(coupling_row(ch, i, s));
  Entries out;
  if (ch.d != 0.0) out.emplace_back(-1, ch.d);
  for (const auto& e : ch.c)
    if (e.first < s) out.push_back(e);
  vs.push_back(out);
  size_t ref = 0;
  for (size_t k = 1; k < vs.size(); ++k)
    if (inf_norm(vs[k]) > inf_norm(vs[ref])) ref = k;
  Cut cut{s, vs[ref], {}};
  if (cut.gamma.empty()) return cut;  // nothing crosses: the transfer is zero
  int pivot = cut.gamma.front().first;
  for (const auto& e : cut.gamma)
    if (std::abs(e.second) > std::abs(value_at(cut.gamma, pivot))) pivot = e.first;
  for (size_t k = 0; k < vs.size(); ++k) {
    double alpha = 0.0;
    if (!proportional(vs[k], cut.gamma, pivot, alpha)) return std::nullopt;
    if (k + 1 < vs.size() && alpha != 0.0) cut.beta.emplace_back(rows[k], alpha);
  }
  return cut;
}

// Every rank-one cut at a group boundary, the first (s = 0) and last (s = n) included.
std::vector<Cut> rank_one_cuts(const Chain& ch) {
  const int n = static_cast<int>(ch.a.rows());
  // Row i crosses the boundary s when first(i) < s <= i, first(i) its first column (-1
  // with an input entry).
  std::vector<std::pair<int, int>> by_first;
  for (int i = 0; i < n; ++i) {
    int first = ch.b(i) != 0.0 ? -1 : n;
    for (SparseMatrix::InnerIterator it(ch.a, i); it; ++it)
      if (it.value() != 0.0) first = std::min(first, static_cast<int>(it.col()));
    if (first < i) by_first.emplace_back(first, i);
  }
  std::sort(by_first.begin(), by_first.end());
  std::vector<Cut> cuts;
  std::vector<int> active;
  size_t next = 0;
  for (int s : ch.starts) {
    while (next < by_first.size() && by_first[next].first < s) active.push_back(by_first[next++].second);
    active.erase(std::remove_if(active.begin(), active.end(), [s](int i) { return i < s; }), active.end());
    std::sort(active.begin(), active.end());
    if (auto c = cut_at(ch, s, active)) cuts.push_back(std::move(*c));
  }
  return cuts;
}

// Modes of `full` (structural values) matching those of `kept` one to one; the others
// go to `hidden`.
std::vector<Complex> matching(const std::vector<Complex>& full, const std::vector<Complex>& kept,
                              std::vector<Complex>& hidden) {
  std::vector<bool> used(full.size(), false);
  for (const Complex& p : kept) {
    size_t best = full.size();
    for (size_t j = 0; j < full.size(); ++j)
      if (!used[j] && (best == full.size() || std::abs(full[j] - p) < std::abs(full[best] - p))) best = j;
    if (best < full.size()) used[best] = true;
  }
  std::vector<Complex> out;
  for (size_t j = 0; j < full.size(); ++j) (used[j] ? out : hidden).push_back(full[j]);
  return out;
}

// One factor: poles by groups (exact integrators), hidden modes by the Krylov rank test
// of StateSpace::minimal, then zeros and gain of what remains by deflation (siso.hpp).
Zpk factor_zpk(const StateSpace& s, std::vector<Complex>& hidden) {
  if (s.num_states() == 0) return Zpk(s.d()(0, 0), 0, {}, {}, s.ts());
  std::vector<Complex> poles = s.poles();
  const StateSpace mn = s.minimal(1e-10);
  if (mn.num_states() < s.num_states()) poles = matching(poles, mn.poles(), hidden);
  const Zpk z = zpk_by_deflation(mn, poles);
  if (z.is_zero()) hidden.insert(hidden.end(), poles.begin(), poles.end());
  return z;
}

// The kept states' chain: group order, b and c gathered.
Chain make_chain(const SparseStateSpace& r, const std::vector<int>& group_sizes) {
  Chain ch{r.a(), Vector::Zero(r.num_states()), {}, r.d()(0, 0), {}, r.ts()};
  for (int i = 0; i < r.num_states(); ++i)
    for (SparseMatrix::InnerIterator it(r.b(), i); it; ++it) ch.b(i) = it.value();
  for (SparseMatrix::InnerIterator it(r.c(), 0); it; ++it) ch.c.emplace_back(static_cast<int>(it.col()), it.value());
  std::sort(ch.c.begin(), ch.c.end());
  int s = 0;
  for (int size : group_sizes) {
    ch.starts.push_back(s);
    s += size;
  }
  ch.starts.push_back(s);
  return ch;
}

// The factor between cuts p and q.
StateSpace factor_between(const Chain& ch, const Cut& p, const Cut& q) {
  const double ts = ch.ts;
  std::vector<int> states;
  for (int i = p.s; i < q.s; ++i) states.push_back(i);
  const auto n = static_cast<Eigen::Index>(states.size());
  Matrix b = Matrix::Zero(n, 1), c = Matrix::Zero(1, n), d(1, 1);
  for (const auto& e : p.beta)
    if (e.first < q.s) b(e.first - p.s, 0) = e.second;
  for (const auto& e : q.gamma)
    if (e.first >= p.s) c(0, e.first - p.s) = e.second;
  int pivot = p.gamma.front().first;
  for (const auto& e : p.gamma)
    if (std::abs(e.second) > std::abs(value_at(p.gamma, pivot))) pivot = e.first;
  d(0, 0) = value_at(q.gamma, pivot) / value_at(p.gamma, pivot);
  // A balanced, then b and c of equal norm (the transfer is unchanged): the couplings
  // of a diagram can put 1e-9 on one side and 1e12 on the other, and the rank tests of
  // minimal() judge b against the size of A.
  const StateSpace bal = StateSpace(dense_block(ch.a, states, states), b, c, d, ts).balanced();
  const double nb = bal.b().norm(), nc = bal.c().norm();
  const double sigma = nb > 0.0 && nc > 0.0 ? std::sqrt(nc / nb) : 1.0;
  return StateSpace(bal.a(), bal.b() * sigma, bal.c() / sigma, d, ts);
}

// The product of the factors between consecutive cuts, zero/pole pairs cancelled
// (kCancelTolerance; exactly at the boundary point, where a zero of one factor and a
// pole of another meet in m). The poles taken out go to `hidden`.
Zpk series_product(const Chain& ch, const std::vector<Cut>& cuts, std::vector<Complex>& hidden) {
  const double ts = ch.ts;
  if (cuts.front().gamma.empty()) return Zpk(0.0, 0, {}, {}, ts);
  double k = cuts.front().gamma.front().second;
  int boundary_poles = 0, boundary_zeros = 0;
  std::vector<Complex> zeros, poles;  // gathered, then sorted once (a chain has thousands)
  for (size_t c = 1; c < cuts.size(); ++c) {
    if (cuts[c].gamma.empty()) return Zpk(0.0, 0, {}, {}, ts);
    const Zpk f = factor_zpk(factor_between(ch, cuts[c - 1], cuts[c]), hidden);
    if (f.is_zero()) return f;
    (f.m() < 0 ? boundary_poles : boundary_zeros) += std::abs(f.m());
    k *= f.k();
    zeros.insert(zeros.end(), f.zeros().begin(), f.zeros().end());
    poles.insert(poles.end(), f.poles().begin(), f.poles().end());
  }
  hidden.insert(hidden.end(), static_cast<size_t>(std::min(boundary_poles, boundary_zeros)),
                Complex(ts > 0.0 ? 1.0 : 0.0, 0.0));
  const Zpk z(k, boundary_zeros - boundary_poles, std::move(zeros), std::move(poles), ts);
  return z.zeros().empty() ? z : z.cancelled(Siso::kCancelTolerance, &hidden);
}

// The verdict from the blocks of the groups the input reaches and the output sees
// (decided by the structure alone), each exactly as the model has it (VerdictBuilder).
// Every mode of those groups counts: a mode that the rank test of minimal() or a
// cancellation within 1e-7 takes out of the transfer is hidden by a tolerance, which
// cannot prove it away (a badly scaled companion of order 5 loses every mode to that
// test). Poles at the boundary point: as the blocks have them, less those the factored
// transfer cancels exactly there.
Stability certified_verdict(const Zpk& z, const std::vector<Matrix>& blocks, bool discrete) {
  VerdictBuilder v(discrete);
  for (const Matrix& a : blocks) v.add_matrix(a);
  const int seen_at_x0 = z.is_zero() ? v.at_boundary_point() : std::max(0, -z.m());
  return v.verdict(std::max(0, v.at_boundary_point() - seen_at_x0));
}

}  // namespace

Zpk zpk_by_interpolation(const StateSpace& sys, const std::vector<Complex>& poles) {
  const Polynomial num = sys.numerator(poles);
  const double ts = sys.ts();
  if (num.is_zero()) return Zpk(0.0, 0, {}, {}, ts);
  const double x0 = ts > 0.0 ? 1.0 : 0.0;
  const auto [rest, zeros_at_x0] = num.without_root(x0);
  double log_k = std::log(std::abs(rest(x0))), sign = rest(x0) < 0.0 ? -1.0 : 1.0;
  int poles_at_x0 = 0;
  std::vector<Complex> others;
  for (const Complex& p : poles) {
    if (p == Complex(x0, 0.0)) {
      ++poles_at_x0;
      continue;
    }
    others.push_back(p);
    log_k -= std::log(std::abs(x0 - p));
    if (p.imag() == 0.0 && x0 - p.real() < 0.0) sign = -sign;
  }
  return Zpk(sign * std::exp(log_k), zeros_at_x0 - poles_at_x0, rest.roots(), others, ts);
}

Siso Siso::from_tf(const TransferFunction& g) {
  Siso s;
  s.zpk_ = Zpk::from_tf(g);
  s.tf_ = g;
  s.coefficients_are_data_ = true;
  s.modes_ = g.poles();
  const double x0 = g.is_discrete() ? 1.0 : 0.0;
  const TransferFunction::Split n = g.split_num(), d = g.split_den();
  const int mn = n.m, md = d.m;
  const int common = g.num().is_zero() ? 0 : std::min(mn, md);
  s.hidden_.assign(static_cast<size_t>(common), Complex(x0, 0.0));
  s.verdict_ = certified_stability(g);
  if (g.is_proper()) {
    const Polynomial root({-x0, 1.0});
    FactorList nf = n.factors, df = d.factors;
    if (mn > common) nf.push_back({root, mn - common});
    if (md > common) df.push_back({root, md - common});
    const TransferFunction reduced =
        common == 0 ? g : TransferFunction(n.rest * root.pow(mn - common), d.rest * root.pow(md - common), g.ts()).with_factors(nf, df);
    s.realisation_ = SparseStateSpace(StateSpace::from_tf(reduced));
  }
  return s;
}

Siso Siso::minreal(double rel_tol, std::vector<Complex>* removed) const {
  if (!(rel_tol >= 0.0) || !std::isfinite(rel_tol))
    throw InputError("a cancellation tolerance must be a finite number >= 0");
  std::vector<Complex> gone;
  const Zpk reduced = zpk_.cancelled(rel_tol, &gone);
  Siso s = *this;
  s.zpk_ = reduced;
  s.hidden_.insert(s.hidden_.end(), gone.begin(), gone.end());
  sort_roots(s.hidden_);
  s.factors_ = 1;
  s.tf_ = reduced.to_tf();
  s.coefficients_are_data_ = false;
  s.dense_.reset();
  s.verdict_ = stability(reduced);
  s.realisation_.reset();
  if (s.tf_ && s.tf_->is_proper()) s.realisation_ = SparseStateSpace(StateSpace::from_tf(*s.tf_));
  if (removed) *removed = gone;
  return s;
}

Siso Siso::from_state_space(const SparseStateSpace& sys) {
  if (sys.num_inputs() != 1 || sys.num_outputs() != 1)
    throw InputError("a SISO analysis needs one input and one output: the model has " +
                     std::to_string(sys.num_inputs()) + " inputs and " + std::to_string(sys.num_outputs()) + " outputs");
  Siso out;
  out.modes_ = sys.poles();
  const std::vector<std::vector<int>> groups = sys.groups();
  const std::vector<bool> keep = relevant_groups(sys, groups);
  std::vector<int> kept, sizes;
  std::vector<Matrix> kept_blocks;  // for the certified verdict
  for (size_t g = 0; g < groups.size(); ++g) {
    if (keep[g]) {
      kept.insert(kept.end(), groups[g].begin(), groups[g].end());
      sizes.push_back(static_cast<int>(groups[g].size()));
      kept_blocks.push_back(dense_block(sys.a(), groups[g], groups[g]));
    } else {
      const std::vector<Complex> ev = group_eigenvalues(dense_block(sys.a(), groups[g], groups[g]), sys.is_discrete());
      out.hidden_.insert(out.hidden_.end(), ev.begin(), ev.end());
    }
  }
  const SparseStateSpace r = sys.restricted(kept);
  const Chain ch = make_chain(r, sizes);
  const std::vector<Cut> cuts = rank_one_cuts(ch);
  out.factors_ = static_cast<int>(cuts.size()) - 1;
  out.zpk_ = series_product(ch, cuts, out.hidden_);
  if (out.zpk_.is_zero()) out.hidden_ = out.modes_;
  out.tf_ = out.zpk_.to_tf();
  out.verdict_ = certified_verdict(out.zpk_, kept_blocks, sys.is_discrete());
  out.realisation_ = r.balanced();
  if (r.num_states() <= kExactStates) out.dense_ = out.realisation_->dense();
  sort_roots(out.hidden_);
  return out;
}

Siso::Step Siso::step(double t_end, int n) const {
  if (!realisation_)
    throw InputError("a step response needs a proper transfer function (numerator degree " +
                     std::to_string(tf_->num().degree()) + " > denominator degree " + std::to_string(tf_->den().degree()) +
                     ")");
  const SparseStep st(*realisation_, t_end, n);
  Step out{st.response(), {}};
  if (verdict_ != Stability::Stable) return out;
  std::vector<double> y(out.response.t.size());
  for (size_t k = 0; k < y.size(); ++k) y[k] = out.response.y(static_cast<Eigen::Index>(k), 0);
  std::function<double(double)> y_at;
  if (!is_discrete()) y_at = [&st](double t) { return st.at(t); };
  out.info = step_figures(out.response.t, y, *zpk_.dc_gain(), y_at);
  return out;
}

std::optional<Complex> Siso::response(double w) const {
  std::optional<Complex> h;
  if (coefficients_are_data_) {
    h = tf_->evaluate(is_discrete() ? std::polar(1.0, w * ts()) : Complex(0.0, w));
  } else if (dense_) {
    h = frequency_response(*dense_, {w}).front()(0, 0);
  }
  if (h && !std::isfinite(std::abs(*h))) h.reset();
  return h;
}

double Siso::default_step_horizon() const { return step_horizon(zpk_.all_poles(), ts()); }

}  // namespace dmbd::blocks
