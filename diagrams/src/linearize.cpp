#include "dmbd/diagrams/linearize.hpp"
#include "dmbd/diagrams/flat.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <functional>
#include <set>

namespace dmbd::diagrams {

namespace b = dmbd::blocks;

namespace {

using Flat = FlatDiagram;

// Solve (I - G) u = r where G is sparse: Tarjan's strongly connected components of the
// dependency graph (u_i depends on u_j when G(i, j) != 0), visited so that every
// component comes after the ones it depends on.
b::Matrix solve_in_dependency_order(const b::Matrix& g, const b::Matrix& r) {
  const int n = static_cast<int>(g.rows());
  std::vector<std::vector<int>> dep(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (g(i, j) != 0.0) dep[static_cast<size_t>(i)].push_back(j);
  std::vector<int> index(static_cast<size_t>(n), -1), low(static_cast<size_t>(n), 0), stack;
  std::vector<bool> on(static_cast<size_t>(n), false);
  std::vector<std::vector<int>> comps;  // in the order Tarjan closes them: dependencies first
  int counter = 0;
  std::function<void(int)> visit = [&](int v) {
    index[static_cast<size_t>(v)] = low[static_cast<size_t>(v)] = counter++;
    stack.push_back(v);
    on[static_cast<size_t>(v)] = true;
    for (int w : dep[static_cast<size_t>(v)]) {
      if (index[static_cast<size_t>(w)] < 0) {
        visit(w);
        low[static_cast<size_t>(v)] = std::min(low[static_cast<size_t>(v)], low[static_cast<size_t>(w)]);
      } else if (on[static_cast<size_t>(w)]) {
        low[static_cast<size_t>(v)] = std::min(low[static_cast<size_t>(v)], index[static_cast<size_t>(w)]);
      }
    }
    if (low[static_cast<size_t>(v)] == index[static_cast<size_t>(v)]) {
      std::vector<int> comp;
      int w;
      do {
        w = stack.back();
        stack.pop_back();
        on[static_cast<size_t>(w)] = false;
        comp.push_back(w);
      } while (w != v);
      comps.push_back(comp);
    }
  };
  for (int v = 0; v < n; ++v)
    if (index[static_cast<size_t>(v)] < 0) visit(v);
  b::Matrix u = b::Matrix::Zero(n, r.cols());
  std::vector<bool> done(static_cast<size_t>(n), false);
  for (const auto& comp : comps) {
    const int k = static_cast<int>(comp.size());
    // Right-hand side with the already solved entries substituted.
    b::Matrix rhs(k, r.cols());
    b::Matrix block = b::Matrix::Identity(k, k);
    for (int a = 0; a < k; ++a) {
      const int i = comp[static_cast<size_t>(a)];
      rhs.row(a) = r.row(i);
      for (int j : dep[static_cast<size_t>(i)]) {
        if (done[static_cast<size_t>(j)]) {
          rhs.row(a) += g(i, j) * u.row(j);
        } else {
          const auto it = std::find(comp.begin(), comp.end(), j);
          block(a, static_cast<int>(it - comp.begin())) -= g(i, j);
        }
      }
    }
    b::Matrix x;
    if (k == 1) {
      if (!(std::abs(block(0, 0)) > 1e-12))
        throw InputError("algebraic loop: a direct-feedthrough path around a loop has gain 1");
      x = rhs / block(0, 0);
    } else {
      Eigen::FullPivLU<b::Matrix> lu(block);
      if (!(std::abs(lu.determinant()) > 1e-12))
        throw InputError("algebraic loop: the direct-feedthrough path around a loop has gain 1 (I - M D is singular)");
      x = lu.solve(rhs);
    }
    for (int a = 0; a < k; ++a) {
      u.row(comp[static_cast<size_t>(a)]) = x.row(a);
      done[static_cast<size_t>(comp[static_cast<size_t>(a)])] = true;
    }
  }
  return u;
}

b::StateSpace assemble(const Diagram& d, const std::string& from, const std::string& to, bool loop) {
  Flat f(d);
  const Flat::Target inj = f.find(from);
  const Flat::Target meas = loop ? inj : f.find(to);
  const int nd = inj.size, nm = meas.size;
  // Stack the atomic blocks.
  int nx = 0;
  for (const Block* bl : f.atomic) nx += bl->model.num_states();
  b::Matrix A = b::Matrix::Zero(nx, nx), B = b::Matrix::Zero(nx, f.nu), C = b::Matrix::Zero(f.ny, nx),
            D = b::Matrix::Zero(f.ny, f.nu);
  {
    int xo = 0, uo = 0, yo = 0;
    for (const Block* bl : f.atomic) {
      const auto& m = bl->model;
      const int n = m.num_states(), p = m.num_outputs(), q = m.num_inputs();
      A.block(xo, xo, n, n) = m.a();
      B.block(xo, uo, n, q) = m.b();
      C.block(yo, xo, p, n) = m.c();
      D.block(yo, uo, p, q) = m.d();
      xo += n;
      uo += q;
      yo += p;
    }
  }
  // u = M y + E w (w: injection), readers fed from their signal (or replaced at a break).
  b::Matrix M = b::Matrix::Zero(f.nu, f.ny), E = b::Matrix::Zero(f.nu, nd);
  b::Matrix Mm = b::Matrix::Zero(nm, f.ny), Em = b::Matrix::Zero(nm, nd);
  auto feed = [&](b::Matrix& Mx, b::Matrix& Ex, int row, int size, const Flat::Route& route, bool hit) {
    const Flat::Signal& s = f.signals[static_cast<size_t>(route.signal)];
    if (!(loop && hit) && !s.top_input) Mx.block(row, s.offset, size, size) += b::Matrix::Identity(size, size);
    if (hit) Ex.block(row, 0, size, size) += b::Matrix::Identity(size, size);
  };
  for (size_t r = 0; r < f.readers.size(); ++r) {
    const Flat::Reader& rd = f.readers[r];
    if (rd.offset < 0) continue;  // a top-level output: only read when measured
    feed(M, E, rd.offset, rd.size, rd.route, Flat::affects(inj, rd.route, static_cast<int>(r)));
  }
  // Measurement: the value at the target, with the injection if it lies upstream (or,
  // for a loop, the value before the break).
  {
    const bool hit = loop ? false : Flat::affects(inj, meas.route, meas.kind == Flat::Target::Kind::Reader ? meas.index : -1);
    const Flat::Signal& s = f.signals[static_cast<size_t>(meas.route.signal)];
    if (!s.top_input) Mm.block(0, s.offset, nm, nm) += b::Matrix::Identity(nm, nm);
    if (hit) Em += b::Matrix::Identity(nm, nd);
  }
  if (nd != nm && !loop) {
    // Sizes may differ (MIMO); the blocks above were sized per target.
  }
  // Solve u = (M D) u + [M C, E] [x; w] for u. Without feedthrough cycles M D is
  // nilpotent, and chains of large gains (9.5e6 N/m next to 1/M) make I - M D so badly
  // conditioned that a general LU loses every digit; so solve by substitution in
  // dependency order, with a small dense solve only inside each group of mutually
  // dependent entries (a loop through a Pade delay's direct term).
  const b::Matrix MD = M * D;
  b::Matrix rhs(f.nu, nx + nd);
  rhs << M * C, E;
  const b::Matrix sol = solve_in_dependency_order(MD, rhs);
  const b::Matrix KMC = sol.leftCols(nx), KE = sol.rightCols(nd);
  b::Matrix Acl = A + B * KMC, Bcl = B * KE;
  b::Matrix Ccl = Mm * (C + D * KMC), Dcl = Mm * D * KE + Em;
  b::StateSpace sys(Acl, Bcl, Ccl, Dcl, d.ts());
  if (loop) sys = b::StateSpace(sys.a(), sys.b(), -sys.c(), -sys.d(), d.ts());
  // Blocks of very different scales (a 1 ms Pade next to a 9.5e6 N/m spring) make A
  // badly scaled: balance before anyone solves with it.
  return sys.balanced();
}

}  // namespace

b::StateSpace linearize(const Diagram& d, const std::string& from, const std::string& to) {
  return assemble(d, from, to, false);
}

b::StateSpace loop_transfer(const Diagram& d, const std::string& at) { return assemble(d, at, at, true); }

std::vector<std::string> signal_names(const Diagram& d) { return Flat(d).names(); }

}  // namespace dmbd::diagrams
