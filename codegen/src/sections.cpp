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
  std::vector<Section> out;
  std::vector<bool> used(zg.size(), false);
  for (const auto& p : pg) {
    // Zeros for this section: the nearest groups that fit its order.
    std::vector<Complex> z;
    while (z.size() < p.size()) {
      int best = -1;
      for (size_t k = 0; k < zg.size(); ++k) {
        if (used[k] || z.size() + zg[k].size() > p.size()) continue;
        if (best < 0 || distance(zg[k], p) < distance(zg[static_cast<size_t>(best)], p)) best = static_cast<int>(k);
      }
      if (best < 0) {
        // Split a real pair if only that is left and one slot remains.
        bool split = false;
        for (size_t k = 0; k < zg.size() && !split; ++k)
          if (!used[k] && zg[k].size() == 2 && zg[k][0].imag() == 0.0) {
            z.push_back(zg[k][0]);
            zg[k] = {zg[k][1]};
            split = true;
          }
        if (!split) break;
        continue;
      }
      used[static_cast<size_t>(best)] = true;
      z.insert(z.end(), zg[static_cast<size_t>(best)].begin(), zg[static_cast<size_t>(best)].end());
    }
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
  return sections_from_roots(g.zeros(), g.poles(), g.num().leading());
}

}  // namespace dmbd::codegen
