#include "scaled_response.hpp"

#include "dmbd/base/vector_clones.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

namespace dmbd::blocks {

namespace {

Complex horner_z(const std::vector<double>& c, Complex z) {
  Complex v(0.0);
  for (auto it = c.rbegin(); it != c.rend(); ++it) v = v * z + *it;
  return v;
}

// j^k for any integer k.
Complex j_power(int k) {
  switch (((k % 4) + 4) % 4) {
    case 0: return {1.0, 0.0};
    case 1: return {0.0, 1.0};
    case 2: return {-1.0, 0.0};
    default: return {0.0, -1.0};
  }
}

}  // namespace

namespace {

// w^k by repeated products for the usual small |k| (each within an ulp; pow costs more).
double int_power(double w, int k) {
  if (k < -8 || k > 8) return std::pow(w, k);
  double p = 1.0;
  for (int i = 0; i < std::abs(k); ++i) p *= w;
  return k < 0 ? 1.0 / p : p;
}

// p(j sigma_k) for every k at once, coefficient c[i] or c[deg - i] per frequency:
// Horner's step (vr + j vi) j sigma + c = (c - vi sigma) + j vr sigma. With
// sigma = w and the coefficients from the highest power down it is p(jw); with
// sigma = -1/w and them from the constant up, (jw)^-deg p(jw) (1/(jw) = j (-1/w)).
DMBD_VECTOR_CLONES void horner_axis(const std::vector<double>& c, const double* sigma, const unsigned char* reversed, std::size_t n,
                 double* vr, double* vi) {
  std::fill(vr, vr + n, 0.0);
  std::fill(vi, vi + n, 0.0);
  const std::size_t deg = c.empty() ? 0 : c.size() - 1;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double from_top = c[deg - i], from_bottom = c[i];
    for (std::size_t k = 0; k < n; ++k) {
      const double ck = reversed[k] ? from_bottom : from_top;
      const double r = ck - vi[k] * sigma[k];
      vi[k] = vr[k] * sigma[k];
      vr[k] = r;
    }
  }
}

}  // namespace

void scaled_responses(const TransferFunction& g, const std::vector<double>& w, std::vector<ScaledResponse>& out) {
  const std::size_t n = w.size();
  out.resize(n);
  if (g.is_discrete()) {  // |z| = 1: no scaling
    for (std::size_t k = 0; k < n; ++k) {
      const Complex z = std::polar(1.0, w[k] * g.ts());
      out[k] = {horner_z(g.num().coeffs(), z) / horner_z(g.den().coeffs(), z), 0};
    }
    return;
  }
  // Scratch left uninitialised (each entry is written before it is read): value
  // initialisation was a tenth of bode's time.
  const std::unique_ptr<double[]> scratch(new double[5 * n]);
  double *sigma = scratch.get(), *nr = sigma + n, *ni = nr + n, *dr = ni + n, *di = dr + n;
  const std::unique_ptr<unsigned char[]> reversed(new unsigned char[n]);
  for (std::size_t k = 0; k < n; ++k) {
    reversed[k] = std::abs(w[k]) > 1.0;
    sigma[k] = reversed[k] ? -1.0 / w[k] : w[k];
  }
  horner_axis(g.num().coeffs(), sigma, reversed.get(), n, nr, ni);
  horner_axis(g.den().coeffs(), sigma, reversed.get(), n, dr, di);
  const int relative = g.num().degree() - g.den().degree();
  for (std::size_t k = 0; k < n; ++k)
    out[k] = {Complex(nr[k], ni[k]) / Complex(dr[k], di[k]), reversed[k] ? relative : 0};
}

Complex ScaledResponse::value(double w) const {
  if (k == 0) return h;
  return h * j_power(k) * int_power(w, k);
}

double ScaledResponse::mag_db(double w) const {
  // One log of |G|^2 where it stays well inside the range (no hypot), else the sum of
  // the parts' logs.
  const double g2 = std::norm(h) * (k == 0 ? 1.0 : int_power(w * w, k));
  if (g2 > 1e-290 && g2 < 1e290) return 10.0 * std::log10(g2);
  const double m = 20.0 * std::log10(std::abs(h));
  return k == 0 ? m : m + 20.0 * k * std::log10(std::abs(w));
}

// arg (jw)^k = k pi/2 for w > 0 and -k pi/2 for w < 0.
double ScaledResponse::arg_rad(double w) const {
  const double a = std::atan2(h.imag(), h.real());
  return k == 0 ? a : a + k * (w < 0.0 ? -M_PI / 2.0 : M_PI / 2.0);
}

}  // namespace dmbd::blocks
