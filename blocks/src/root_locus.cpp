#include "dmbd/blocks/root_locus.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

namespace {

void check_gain(double k) {
  if (!std::isfinite(k)) throw InputError("gains: expected finite gains, got " + std::to_string(k));
}

// The roots of den + k num, with +inf for those lost to a drop in degree.
std::vector<Complex> closed_loop_roots(const TransferFunction& g, double k) {
  std::vector<Complex> r = (g.den() + k * g.num()).roots();
  r.resize(static_cast<size_t>(g.order()), Complex(std::numeric_limits<double>::infinity(), 0.0));
  return r;
}

// Row by row, each root to the nearest remaining column of the previous row.
ComplexMatrix sorted_rows(const std::vector<std::vector<Complex>>& rows, Eigen::Index order) {
  ComplexMatrix out(static_cast<Eigen::Index>(rows.size()), order);
  for (size_t i = 0; i < rows.size(); ++i) {
    std::vector<Complex> row = rows[i];
    if (i == 0) {
      sort_roots(row);
      for (Eigen::Index c = 0; c < order; ++c) out(0, c) = row[static_cast<size_t>(c)];
      continue;
    }
    std::vector<Eigen::Index> available;
    for (Eigen::Index c = 0; c < order; ++c) available.push_back(c);
    for (const Complex& r : row) {
      size_t best = 0;
      double dist = std::numeric_limits<double>::infinity();
      for (size_t a = 0; a < available.size(); ++a) {
        const double d = std::abs(r - out(static_cast<Eigen::Index>(i - 1), available[a]));
        if (d < dist) {
          dist = d;
          best = a;
        }
      }
      out(static_cast<Eigen::Index>(i), available[best]) = r;
      available.erase(available.begin() + static_cast<std::ptrdiff_t>(best));
    }
  }
  return out;
}

}  // namespace

ComplexMatrix root_locus(const TransferFunction& g, const std::vector<double>& gains) {
  if (!g.is_proper()) throw InputError("root locus: the transfer function is improper (more zeros than poles)");
  std::vector<std::vector<Complex>> rows;
  for (double k : gains) {
    check_gain(k);
    rows.push_back(closed_loop_roots(g, k));
  }
  return sorted_rows(rows, g.order());
}

ComplexMatrix root_locus(const StateSpace& g, const std::vector<double>& gains) {
  if (g.num_inputs() != 1 || g.num_outputs() != 1)
    throw InputError("root locus: needs one input and one output, the model has " + std::to_string(g.num_inputs()) +
                     " inputs and " + std::to_string(g.num_outputs()) + " outputs");
  const double d = g.d()(0, 0);
  std::vector<std::vector<Complex>> rows;
  for (double k : gains) {
    check_gain(k);
    const double den = 1.0 + k * d;
    if (std::abs(den) <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(k * d))) {
      rows.push_back(closed_loop_roots(g.to_tf(), k));
      continue;
    }
    const Matrix acl = g.a() - (k / den) * g.b() * g.c();
    const Eigen::EigenSolver<Matrix> es(acl, false);
    rows.emplace_back(es.eigenvalues().data(), es.eigenvalues().data() + es.eigenvalues().size());
  }
  return sorted_rows(rows, g.num_states());
}

std::vector<double> default_root_locus_gains(const TransferFunction& g) {
  double log_sum = 0.0;
  int count = 0;
  for (const auto& roots : {g.poles(), g.zeros()})
    for (const Complex& r : roots) {
      const double mag = g.is_discrete() ? std::abs(std::log(r)) / g.ts() : std::abs(r);
      if (mag > 0.0 && std::isfinite(mag)) {
        log_sum += std::log(mag);
        ++count;
      }
    }
  double w0 = count ? std::exp(log_sum / count) : 1.0;
  if (g.is_discrete()) w0 = std::min(w0, 0.5 * M_PI / g.ts());
  const Complex x = g.is_discrete() ? std::polar(1.0, w0 * g.ts()) : Complex(0.0, w0);
  double k0 = 1.0 / std::abs(g.evaluate(x));
  if (!(k0 > 0.0) || !std::isfinite(k0)) k0 = 1.0;
  std::vector<double> k{0.0};
  for (double v : logspace(k0 * 1e-3, k0 * 1e3, 200)) k.push_back(v);
  return k;
}

}  // namespace dmbd::blocks
