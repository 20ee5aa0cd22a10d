#include "dmbd/blocks/delay.hpp"

#include <cmath>
#include <string>

#include "dmbd/blocks/error.hpp"

namespace dmbd::blocks {

TransferFunction pade(double delay_s, int order) {
  if (!(delay_s >= 0.0) || !std::isfinite(delay_s)) throw InputError("delay must be a finite number of seconds >= 0");
  if (order < 0 || order > 20) throw InputError("Pade order must be between 0 and 20, got " + std::to_string(order));
  if (order == 0 || delay_s == 0.0) return TransferFunction(1.0);
  const int n = order;
  std::vector<double> num(static_cast<size_t>(n) + 1), den(static_cast<size_t>(n) + 1);
  double c = 1.0, tk = 1.0;  // c_k = (2n-k)! n! / ((2n)! k! (n-k)!), tk = T^k
  for (int k = 0; k <= n; ++k) {
    den[static_cast<size_t>(k)] = c * tk;
    num[static_cast<size_t>(k)] = (k % 2 ? -1.0 : 1.0) * c * tk;
    c *= static_cast<double>(n - k) / (static_cast<double>(2 * n - k) * static_cast<double>(k + 1));
    tk *= delay_s;
  }
  return TransferFunction(Polynomial(num), Polynomial(den));
}

TransferFunction sample_delay(int n, double ts) {
  if (!(ts > 0.0)) throw InputError("a sample delay needs a positive sample time");
  if (n < 0) throw InputError("a sample delay must be >= 0 samples, got " + std::to_string(n));
  return TransferFunction(Polynomial::constant(1.0), Polynomial::monomial(n), ts);
}

TransferFunction thiran(double delay_samples, int order, double ts) {
  if (!(ts > 0.0)) throw InputError("a Thiran delay needs a positive sample time");
  if (order < 1 || order > 20) throw InputError("Thiran order must be between 1 and 20");
  const int n = order;
  const double d = delay_samples;
  if (!(d > n - 1)) throw InputError("a Thiran filter of order " + std::to_string(n) + " needs a delay above " +
                                     std::to_string(n - 1) + " samples to be stable, got " + std::to_string(d));
  std::vector<double> a(static_cast<size_t>(n) + 1);
  double binom = 1.0;  // C(n, k)
  for (int k = 0; k <= n; ++k) {
    // a_0 = 1; for k >= 1 the product has the factor (d - n) that makes an integer delay
    // d = n a pure z^-n (computed as 0/0 at k = 0, hence the special case).
    double prod = 1.0;
    for (int i = 0; i <= n && k > 0; ++i) prod *= (d - n + i) / (d - n + k + i);
    a[static_cast<size_t>(k)] = (k % 2 ? -1.0 : 1.0) * binom * prod;
    binom = binom * (n - k) / (k + 1);
  }
  // H(z) = (a_n + a_{n-1} z^-1 + ... + z^-n) / (1 + a_1 z^-1 + ... + a_n z^-n), times z^n / z^n.
  std::vector<double> den(a.rbegin(), a.rend());  // ascending: a_n, ..., a_1, 1
  return TransferFunction(Polynomial(a), Polynomial(den), ts);
}

}  // namespace dmbd::blocks
