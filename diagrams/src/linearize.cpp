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
  const b::Matrix sol = b::solve_in_dependency_order(MD, rhs);
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
