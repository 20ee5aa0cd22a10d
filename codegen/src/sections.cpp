// Second-order sections of discrete transfer functions.
#include <algorithm>
#include <cmath>
#include <limits>

#include "dmbd/blocks/error.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "sections.hpp"

namespace dmbd::codegen {

namespace b = dmbd::blocks;
using b::Complex;

namespace {

// Roots grouped as conjugate pairs, real pairs, and at most one single real root.
std::vector<std::vector<Complex>> group(std::vector<Complex> r) {
  std::vector<std::vector<Complex>> out;
  std::vector<Complex> real;
  for (const Complex& x : r) {
    if (x.imag() > 0.0) out.push_back({x, std::conj(x)});
    if (x.imag() == 0.0) real.push_back(x);
  }
  std::sort(real.begin(), real.end(), [](const Complex& p, const Complex& q) { return p.real() < q.real(); });
  for (size_t k = 0; k + 1 < real.size(); k += 2) out.push_back({real[k], real[k + 1]});
  if (real.size() % 2) out.push_back({real.back()});
  return out;
}

double distance(const std::vector<Complex>& a, const std::vector<Complex>& b) {
  double d = std::numeric_limits<double>::infinity();
  for (const Complex& x : a)
    for (const Complex& y : b) d = std::min(d, std::abs(x - y));
  return d;
}

}  // namespace

std::vector<Section> sections_from_roots(const std::vector<Complex>& zeros, const std::vector<Complex>& poles,
                                         double gain) {
  if (zeros.size() > poles.size()) throw InputError("an improper transfer function has no second-order sections");
  // Exact conjugates and exact reals, as roots() delivers them.
  std::vector<std::vector<Complex>> pg = group(poles), zg = group(zeros);
  // Sections from the pole group nearest the unit circle first (it gets the nearest
  // zeros); emitted in the reverse order, nearest last (MATLAB zp2sos 'up').
  std::sort(pg.begin(), pg.end(), [](const auto& x, const auto& y) {
    double dx = 0, dy = 0;
    for (const auto& p : x) dx = std::max(dx, std::abs(p));
    for (const auto& p : y) dy = std::max(dy, std::abs(p));
    return dx > dy;
  });
  // Zeros to sections: every complex pair to a second-order section (there are at least
  // as many as complex zero pairs, since real poles are paired two by two), nearest
  // first; then every real zero to the nearest section with a free slot.
  std::vector<std::vector<Complex>> zs(pg.size());
  auto nearest = [&](const std::vector<Complex>& z, size_t need) {
    int best = -1;
    for (size_t k = 0; k < pg.size(); ++k) {
      if (pg[k].size() - zs[k].size() < need) continue;
      if (best < 0 || distance(z, pg[k]) < distance(z, pg[static_cast<size_t>(best)])) best = static_cast<int>(k);
    }
    return best;
  };
  std::vector<Complex> real_zeros;
  for (const auto& g : zg) {
    if (g.size() == 2 && g[0].imag() != 0.0) {
      const int k = nearest(g, 2);
      if (k < 0) throw InputError("internal: no second-order section left for a complex zero pair");
      zs[static_cast<size_t>(k)] = g;
    } else {
      real_zeros.insert(real_zeros.end(), g.begin(), g.end());
    }
  }
  for (const Complex& z : real_zeros) {
    const int k = nearest({z}, 1);
    if (k < 0) throw InputError("internal: no section left for a real zero");
    zs[static_cast<size_t>(k)].push_back(z);
  }
  std::vector<Section> out;
  for (size_t gi = 0; gi < pg.size(); ++gi) {
    const auto& p = pg[gi];
    const std::vector<Complex>& z = zs[gi];
    Section s;
    s.order = static_cast<int>(p.size());
    // Denominator 1 + a1 z^-1 + a2 z^-2 from the poles.
    if (p.size() == 2) {
      s.a1 = -(p[0] + p[1]).real();
      s.a2 = (p[0] * p[1]).real();
    } else {
      s.a1 = -p[0].real();
    }
    // Numerator: finite zeros give (1 - z z^-1); the missing ones are zeros at infinity,
    // pure delays z^-1 (a strictly proper system has no direct feedthrough).
    std::vector<double> num{1.0};
    if (z.size() == 2) num = {1.0, -(z[0] + z[1]).real(), (z[0] * z[1]).real()};
    if (z.size() == 1) num = {1.0, -z[0].real()};
    std::vector<double> bz(p.size() + 1, 0.0);
    const size_t shift = p.size() - z.size();
    for (size_t k = 0; k < num.size() && k + shift < bz.size(); ++k) bz[k + shift] = num[k];
    s.b0 = bz[0];
    s.b1 = bz.size() > 1 ? bz[1] : 0.0;
    s.b2 = bz.size() > 2 ? bz[2] : 0.0;
    out.push_back(s);
  }
  std::reverse(out.begin(), out.end());  // farthest from the unit circle first
  if (out.empty()) {
    Section s;
    s.b0 = gain;
    s.order = 0;  // a static gain
    return {s};
  }
  out.front().b0 *= gain;
  out.front().b1 *= gain;
  out.front().b2 *= gain;
  return out;
}

std::vector<Section> second_order_sections(const b::TransferFunction& g) {
  if (!g.is_discrete()) throw InputError("second-order sections need a discrete transfer function");
  if (!g.is_proper()) throw InputError("an improper transfer function has no second-order sections");
  // Roots at z = -1, 0 and 1 (Tustin's zeros at infinity, pure delays, integrators) are
  // divided out exactly first: as repeated roots the general root finder would scatter
  // them by eps^(1/n).
  auto roots = [](const b::Polynomial& p) {
    b::Polynomial rest = p;
    std::vector<Complex> r;
    for (double x0 : {-1.0, 0.0, 1.0}) {
      const auto [q, m] = rest.without_root(x0);
      rest = q;
      for (int k = 0; k < m; ++k) r.emplace_back(x0, 0.0);
    }
    const auto others = rest.roots();
    r.insert(r.end(), others.begin(), others.end());
    return r;
  };
  // A zero numerator (a gain parameter at 0) has no roots: the poles keep their states.
  const std::vector<Complex> zeros = g.num().is_zero() ? std::vector<Complex>{} : roots(g.num());
  return sections_from_roots(zeros, roots(g.den()), g.num().leading());
}

}  // namespace dmbd::codegen
