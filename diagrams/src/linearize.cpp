#include "dmbd/diagrams/linearize.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "dmbd/diagrams/flat.hpp"

namespace dmbd::diagrams {

namespace b = dmbd::blocks;

namespace {

using Flat = FlatDiagram;
// A sparse row over the columns [x (all states); w (the injected input)], sorted.
using Row = std::vector<std::pair<int, double>>;

// Sums of scaled sparse rows into a dense scratch, gathered back sorted. A sum that
// cancels to rounding (|sum| <= 16 eps times its largest term: unity feedback around
// a filter, A_Q + B_Q C_Q) is exactly zero: the exact model has no entry there, and a
// residue of 1e-14 would couple states that are not coupled (an integrator inside a
// loop group instead of a state of its own, and balancing that scales by 2^27).
class Accumulator {
 public:
  explicit Accumulator(int width)
      : value_(static_cast<size_t>(width), 0.0), biggest_(static_cast<size_t>(width), 0.0),
        used_(static_cast<size_t>(width), false) {}
  void add(int col, double v) {
    if (v == 0.0) return;
    const auto c = static_cast<size_t>(col);
    if (!used_[c]) used_[c] = true, touched_.push_back(col);
    value_[c] += v;
    biggest_[c] = std::max(biggest_[c], std::abs(v));
  }
  void add(const Row& r, double scale) {
    if (scale != 0.0)
      for (const auto& [c, v] : r) add(c, scale * v);
  }
  Row take() {
    std::sort(touched_.begin(), touched_.end());
    Row r;
    for (int col : touched_) {
      const auto c = static_cast<size_t>(col);
      if (std::abs(value_[c]) > kCancelled * biggest_[c]) r.emplace_back(col, value_[c]);
      value_[c] = biggest_[c] = 0.0;
      used_[c] = false;
    }
    touched_.clear();
    return r;
  }

 private:
  static constexpr double kCancelled = 16.0 * std::numeric_limits<double>::epsilon();
  std::vector<double> value_, biggest_;
  std::vector<bool> used_;
  std::vector<int> touched_;
};

// The diagram's blocks stacked (block-diagonal A, B, C, D, as offsets into each
// block's own model) and how every scalar block input is fed.
struct Layout {
  std::vector<int> xo, uo, yo;   // per atomic block: first state, input entry, output entry
  std::vector<int> block_of_u;   // per input entry: its atomic block
  std::vector<int> source;       // per input entry: the output entry it reads, or -1
  std::vector<int> injected;     // per input entry: the injection entry added to it, or -1
  int nx = 0, nu = 0, ny = 0, nd = 0;
};

// Injected inputs: a place and the first column of its entries in w.
struct Injection {
  Flat::Target at;
  int column;
};

Layout layout(const Flat& f, const std::vector<Injection>& injections, bool loop) {
  Layout l;
  for (size_t k = 0; k < f.atomic.size(); ++k) {
    const b::StateSpace& m = f.atomic[k]->model;
    l.xo.push_back(l.nx);
    l.uo.push_back(l.nu);
    l.yo.push_back(l.ny);
    l.nx += m.num_states();
    l.nu += m.num_inputs();
    l.ny += m.num_outputs();
    l.block_of_u.insert(l.block_of_u.end(), static_cast<size_t>(m.num_inputs()), static_cast<int>(k));
  }
  for (const Injection& j : injections) l.nd = std::max(l.nd, j.column + j.at.size);
  l.source.assign(static_cast<size_t>(l.nu), -1);
  l.injected.assign(static_cast<size_t>(l.nu), -1);
  for (size_t r = 0; r < f.readers.size(); ++r) {
    const Flat::Reader& rd = f.readers[r];
    if (rd.offset < 0) continue;  // a top-level output: only read when measured
    int column = -1;  // the injection this reader sees (distinct places: at most one)
    for (const Injection& j : injections)
      if (Flat::affects(j.at, rd.route, static_cast<int>(r))) column = j.column;
    const bool hit = column >= 0;
    const Flat::Signal& s = f.signals[static_cast<size_t>(rd.route.signal)];
    for (int t = 0; t < rd.size; ++t) {
      if (!(loop && hit) && !s.top_input) l.source[static_cast<size_t>(rd.offset + t)] = s.offset + t;
      if (hit) l.injected[static_cast<size_t>(rd.offset + t)] = column + t;
    }
  }
  return l;
}

// Which block and which of its output rows an output entry is.
struct OutputEntry {
  int block, row;
};

std::vector<OutputEntry> output_entries(const Flat& f) {
  std::vector<OutputEntry> out;
  for (size_t k = 0; k < f.atomic.size(); ++k)
    for (int r = 0; r < f.atomic[k]->model.num_outputs(); ++r) out.push_back({static_cast<int>(k), r});
  return out;
}

// Adds output entry e = C x + D u of its block, with the inputs' rows where `solved`
// (the others are unknowns of the caller; their coefficients go to `unknown`).
void add_output(const Flat& f, const Layout& l, const OutputEntry& e, const std::vector<Row>& u,
                const std::vector<bool>& solved, Accumulator& acc, std::vector<std::pair<int, double>>* unknown = nullptr) {
  const b::StateSpace& m = f.atomic[static_cast<size_t>(e.block)]->model;
  const auto k = static_cast<size_t>(e.block);
  for (int c = 0; c < m.num_states(); ++c) acc.add(l.xo[k] + c, m.c()(e.row, c));
  for (int c = 0; c < m.num_inputs(); ++c) {
    const int i = l.uo[k] + c;
    const double g = m.d()(e.row, c);
    if (g == 0.0) continue;
    if (solved[static_cast<size_t>(i)]) {
      acc.add(u[static_cast<size_t>(i)], g);
    } else if (unknown) {
      unknown->emplace_back(i, g);
    }
  }
}

// u_i = (its injection) + (the output entry it reads), known parts into acc.
void add_input(const Flat& f, const Layout& l, const std::vector<OutputEntry>& outs, int i, const std::vector<Row>& u,
               const std::vector<bool>& solved, Accumulator& acc, std::vector<std::pair<int, double>>* unknown = nullptr) {
  if (l.injected[static_cast<size_t>(i)] >= 0) acc.add(l.nx + l.injected[static_cast<size_t>(i)], 1.0);
  const int j = l.source[static_cast<size_t>(i)];
  if (j >= 0) add_output(f, l, outs[static_cast<size_t>(j)], u, solved, acc, unknown);
}

// A group of mutually dependent input entries: (I - G) u_g = r_g, dense.
void solve_group(const Flat& f, const Layout& l, const std::vector<OutputEntry>& outs, const std::vector<int>& group,
                 std::vector<Row>& u, const std::vector<bool>& solved, Accumulator& acc) {
  const auto k = static_cast<Eigen::Index>(group.size());
  b::Matrix m = b::Matrix::Identity(k, k);
  std::vector<Row> rhs;
  for (Eigen::Index a = 0; a < k; ++a) {
    std::vector<std::pair<int, double>> unknown;
    add_input(f, l, outs, group[static_cast<size_t>(a)], u, solved, acc, &unknown);
    rhs.push_back(acc.take());
    for (const auto& [i, g] : unknown)
      m(a, std::find(group.begin(), group.end(), i) - group.begin()) -= g;
  }
  std::vector<int> cols;
  for (const Row& r : rhs)
    for (const auto& e : r) cols.push_back(e.first);
  std::sort(cols.begin(), cols.end());
  cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
  b::Matrix r = b::Matrix::Zero(k, static_cast<Eigen::Index>(cols.size()));
  for (Eigen::Index a = 0; a < k; ++a)
    for (const auto& [c, v] : rhs[static_cast<size_t>(a)])
      r(a, std::lower_bound(cols.begin(), cols.end(), c) - cols.begin()) = v;
  b::Matrix x;
  if (k == 1) {
    if (!(std::abs(m(0, 0)) > 1e-12)) throw InputError("algebraic loop: a direct-feedthrough path around a loop has gain 1");
    x = r / m(0, 0);
  } else {
    Eigen::FullPivLU<b::Matrix> lu(m);
    if (!(std::abs(lu.determinant()) > 1e-12))
      throw InputError("algebraic loop: the direct-feedthrough path around a loop has gain 1 (I - M D is singular)");
    x = lu.solve(r);
  }
  for (Eigen::Index a = 0; a < k; ++a) {
    for (size_t c = 0; c < cols.size(); ++c) acc.add(cols[c], x(a, static_cast<Eigen::Index>(c)));
    u[static_cast<size_t>(group[static_cast<size_t>(a)])] = acc.take();
  }
}

// The rows of every input entry: u = (the output entry it reads) + (its injection),
// solved in dependency order (u_i depends on u_k through the direct feedthrough of the
// block it reads). Chains of large gains (9.5e6 N/m next to 1/M) make a general LU of
// I - M D lose every digit, so only each group of mutually dependent entries (a loop
// through a Pade delay's direct term) gets a small dense solve.
std::vector<Row> input_rows(const Flat& f, const Layout& l, const std::vector<OutputEntry>& outs) {
  std::vector<std::vector<int>> dep(static_cast<size_t>(l.nu));
  for (int i = 0; i < l.nu; ++i) {
    const int j = l.source[static_cast<size_t>(i)];
    if (j < 0) continue;
    const OutputEntry& e = outs[static_cast<size_t>(j)];
    const b::StateSpace& m = f.atomic[static_cast<size_t>(e.block)]->model;
    for (int c = 0; c < m.num_inputs(); ++c)
      if (m.d()(e.row, c) != 0.0) dep[static_cast<size_t>(i)].push_back(l.uo[static_cast<size_t>(e.block)] + c);
  }
  std::vector<Row> u(static_cast<size_t>(l.nu));
  std::vector<bool> solved(static_cast<size_t>(l.nu), false);
  Accumulator acc(l.nx + l.nd);
  for (const std::vector<int>& group : b::strongly_connected_components(dep)) {
    const auto& d0 = dep[static_cast<size_t>(group.front())];
    if (group.size() == 1 && std::find(d0.begin(), d0.end(), group.front()) == d0.end()) {
      add_input(f, l, outs, group.front(), u, solved, acc);
      u[static_cast<size_t>(group.front())] = acc.take();
    } else {
      solve_group(f, l, outs, group, u, solved, acc);
    }
    for (int i : group) solved[static_cast<size_t>(i)] = true;
  }
  return u;
}

// Sparse matrices from rows over [x; w]: the x part and the w part.
void split_rows(const std::vector<Row>& rows, int nx, int nd, b::SparseMatrix& xs, b::SparseMatrix& ws) {
  std::vector<Eigen::Triplet<double>> tx, tw;
  for (size_t r = 0; r < rows.size(); ++r)
    for (const auto& [c, v] : rows[r]) (c < nx ? tx : tw).emplace_back(static_cast<int>(r), c < nx ? c : c - nx, v);
  xs = b::SparseMatrix(static_cast<Eigen::Index>(rows.size()), nx);
  ws = b::SparseMatrix(static_cast<Eigen::Index>(rows.size()), nd);
  xs.setFromTriplets(tx.begin(), tx.end());
  ws.setFromTriplets(tw.begin(), tw.end());
}

// x' = A_b x_b + B_b u_b, block by block, as rows over [x; w].
std::vector<Row> state_rows(const Flat& f, const Layout& l, const std::vector<Row>& u, Accumulator& acc) {
  std::vector<Row> rows;
  for (size_t k = 0; k < f.atomic.size(); ++k) {
    const b::StateSpace& m = f.atomic[k]->model;
    for (int i = 0; i < m.num_states(); ++i) {
      for (int c = 0; c < m.num_states(); ++c) acc.add(l.xo[k] + c, m.a()(i, c));
      for (int c = 0; c < m.num_inputs(); ++c) acc.add(u[static_cast<size_t>(l.uo[k] + c)], m.b()(i, c));
      rows.push_back(acc.take());
    }
  }
  return rows;
}

b::SparseStateSpace assemble(const Diagram& d, const std::string& from, const std::string& to, bool loop) {
  Flat f(d);
  const Flat::Target inj = f.find(from);
  const Flat::Target meas = loop ? inj : f.find(to);
  const Layout l = layout(f, {{inj, 0}}, loop);
  const std::vector<OutputEntry> outs = output_entries(f);
  const std::vector<Row> u = input_rows(f, l, outs);
  const std::vector<bool> solved(static_cast<size_t>(l.nu), true);
  Accumulator acc(l.nx + l.nd);
  const std::vector<Row> states = state_rows(f, l, u, acc);
  // The measurement: the value at the target, with the injection if it lies upstream
  // (for a loop, the value before the break, negated).
  std::vector<Row> meas_rows;
  const bool hit = !loop && Flat::affects(inj, meas.route, meas.kind == Flat::Target::Kind::Reader ? meas.index : -1);
  const Flat::Signal& s = f.signals[static_cast<size_t>(meas.route.signal)];
  for (int t = 0; t < meas.size; ++t) {
    if (!s.top_input) add_output(f, l, outs[static_cast<size_t>(s.offset + t)], u, solved, acc);
    if (hit && t < l.nd) acc.add(l.nx + t, 1.0);
    meas_rows.push_back(acc.take());
  }
  b::SparseMatrix a, bm, c, dm;
  split_rows(states, l.nx, l.nd, a, bm);
  split_rows(meas_rows, l.nx, l.nd, c, dm);
  if (loop) c = -c, dm = -dm;
  return b::SparseStateSpace(a, bm, c, b::Matrix(dm), d.ts());
}

}  // namespace

// Every input of the diagram injected (stacked in order), every output measured.
b::SparseStateSpace assemble_io(const Diagram& d) {
  Flat f(d);
  std::vector<Injection> injections;
  int column = 0;
  for (size_t i = 0; i < d.inputs().size(); ++i) {
    injections.push_back({f.find(d.inputs()[i].name), column});
    column += d.inputs()[i].size;
  }
  const Layout l = layout(f, injections, false);
  const std::vector<OutputEntry> outs = output_entries(f);
  const std::vector<Row> u = input_rows(f, l, outs);
  const std::vector<bool> solved(static_cast<size_t>(l.nu), true);
  Accumulator acc(l.nx + l.nd);
  const std::vector<Row> states = state_rows(f, l, u, acc);
  std::vector<Row> meas_rows;
  for (int r = f.first_top_output; r < static_cast<int>(f.readers.size()); ++r) {
    const Flat::Reader& rd = f.readers[static_cast<size_t>(r)];
    const Flat::Signal& s = f.signals[static_cast<size_t>(rd.route.signal)];
    int hit = -1;
    for (const Injection& j : injections)
      if (Flat::affects(j.at, rd.route, r)) hit = j.column;
    for (int t = 0; t < rd.size; ++t) {
      if (!s.top_input) add_output(f, l, outs[static_cast<size_t>(s.offset + t)], u, solved, acc);
      if (hit >= 0) acc.add(l.nx + hit + t, 1.0);
      meas_rows.push_back(acc.take());
    }
  }
  b::SparseMatrix a, bm, c, dm;
  split_rows(states, l.nx, l.nd, a, bm);
  split_rows(meas_rows, l.nx, l.nd, c, dm);
  return b::SparseStateSpace(a, bm, c, b::Matrix(dm), d.ts());
}

b::StateSpace linearize_io(const Diagram& d) { return assemble_io(d).dense().balanced(); }

b::SparseStateSpace linearize_sparse(const Diagram& d, const std::string& from, const std::string& to) {
  return assemble(d, from, to, false);
}

b::SparseStateSpace loop_transfer_sparse(const Diagram& d, const std::string& at) { return assemble(d, at, at, true); }

// Blocks of very different scales (a 1 ms Pade next to a 9.5e6 N/m spring) make A
// badly scaled: balance before anyone solves with it.
b::StateSpace linearize(const Diagram& d, const std::string& from, const std::string& to) {
  return linearize_sparse(d, from, to).dense().balanced();
}

b::StateSpace loop_transfer(const Diagram& d, const std::string& at) { return loop_transfer_sparse(d, at).dense().balanced(); }

std::vector<std::string> signal_names(const Diagram& d) { return Flat(d).names(); }

}  // namespace dmbd::diagrams
