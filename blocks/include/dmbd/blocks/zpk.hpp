#pragma once
// SISO transfers of any order as zeros, poles and a low-frequency gain: evaluated
// factor by factor in logarithms, so nothing overflows (a chain of 1000 lags is
// -10^4 dB at ten times its corner) and the phase is exact; with frequency responses,
// margins, bandwidth and the stability verdict computed on that form.
#include <optional>
#include <vector>

#include "dmbd/blocks/frequency.hpp"

namespace dmbd::blocks {

// G(s) = k s^m prod(1 - s/z_i) / prod(1 - s/p_j)                 (continuous), or
// G(z) = k (z - 1)^m prod((z - z_i)/(1 - z_i)) / prod((z - p_j)/(1 - p_j))   (discrete):
// normalised at s = 0 (z = 1), the boundary point, so that k is the DC gain when
// m = 0. The z_i and p_j exclude the boundary point: roots there are counted in m
// exactly (zeros minus poles), never left as 1e-13 or 0.99999999993.
class Zpk {
 public:
  // k = 0 is the zero transfer. InputError for a root at the boundary point in the
  // lists, a non-finite root or a non-finite k. The roots are taken as given: that
  // complex ones come in conjugate pairs is the caller's promise (not checked).
  Zpk(double k, int m, std::vector<Complex> zeros, std::vector<Complex> poles, double ts = 0.0);
  // Roots at the boundary point decided by Polynomial::without_root; a common factor
  // s^j ((z - 1)^j) of num and den cancels exactly.
  static Zpk from_tf(const TransferFunction& g);

  // The gain k of the form above: the DC gain when m == 0, the coefficient of the
  // low-frequency asymptote k s^m (k (z - 1)^m) otherwise; 0 for the zero transfer.
  double k() const { return k_; }
  // Zeros minus poles at the boundary point s = 0 (z = 1): m < 0 is -m integrators,
  // m > 0 that many differentiators.
  int m() const { return m_; }
  const std::vector<Complex>& zeros() const { return zeros_; }  // boundary point excluded
  const std::vector<Complex>& poles() const { return poles_; }  // boundary point excluded
  // The same, each distinct root once with its multiplicity: what the evaluations
  // loop over (a chain of 10000 equal lags is one term).
  struct Root {
    Complex value;  // the root (exactly equal roots are one Root)
    int count;      // its multiplicity, >= 1
  };
  const std::vector<Root>& distinct_zeros() const { return distinct_zeros_; }  // sorted as zeros()
  const std::vector<Root>& distinct_poles() const { return distinct_poles_; }  // sorted as poles()
  // Sample time in seconds; 0 when continuous.
  double ts() const { return ts_; }
  // ts() > 0: a function of z, the boundary point z = 1.
  bool is_discrete() const { return ts_ > 0.0; }
  // k == 0: G is identically zero (its roots and m mean nothing).
  bool is_zero() const { return k_ == 0.0; }
  // Every pole (zero), those at the boundary point included, sorted.
  std::vector<Complex> all_poles() const;
  std::vector<Complex> all_zeros() const;  // every zero, likewise
  // The number of poles, those at the boundary point included (the degree of to_tf()'s
  // denominator).
  int order() const { return static_cast<int>(poles_.size()) + std::max(0, -m_); }
  // Poles minus zeros.
  int relative_degree() const { return static_cast<int>(poles_.size() - zeros_.size()) - m_; }
  // k when m = 0, 0 when m > 0, nullopt (infinite) when m < 0.
  std::optional<double> dc_gain() const;

  // log G at w rad/s: real part ln|G|, imaginary part the phase unwrapped from DC as
  // Bode::phase_deg describes, each a sum over the factors. -inf for the zero transfer.
  Complex log_response(double w) const;
  // d/dw of log_response.
  Complex log_slope(double w) const;

  // Series connection.
  friend Zpk operator*(const Zpk& a, const Zpk& b);
  // Zero/pole pairs with |z - p| <= rel_tol |p| removed (each zero with its nearest
  // pole; conjugate pairs together); `removed` receives the poles taken out.
  Zpk cancelled(double rel_tol, std::vector<Complex>* removed = nullptr) const;
  // The rational function, den monic; nullopt when a coefficient overflows.
  std::optional<TransferFunction> to_tf() const;

 private:
  double k_;
  int m_;
  std::vector<Complex> zeros_, poles_;
  double ts_;
  std::vector<Root> distinct_zeros_, distinct_poles_;
};

// A grid two decades beyond the slowest and fastest root (up to Nyquist when discrete).
std::vector<double> default_frequency_grid(const Zpk& g, int n = 400);
// The Bode data from log_response: magnitude and phase exact for any order (no
// polynomial is formed); Bode::response is e^{log G}, which may overflow where mag_db
// does not.
Bode bode(const Zpk& g, const std::vector<double>& w_rad_s);
// As margins(const TransferFunction&): the same conventions, crossings found by
// certified isolation instead of polynomial roots (see zpk.cpp), for any order.
// DC is a phase crossover only when G(0) is finite (m = 0) and negative; there is no
// crossover at a pole on the imaginary axis (unit circle), where |G| is infinite.
Margins margins(const Zpk& loop);
// As bandwidth(const TransferFunction&).
std::optional<double> bandwidth(const Zpk& g, double drop_db = -3.0);

// Stable: every pole strictly inside (Re s < 0, |z| < 1). Marginal: none outside, and
// those on the boundary simple. Unstable: otherwise (a double integrator is unstable).
// A pole is on the boundary when it is exactly at s = 0 (z = 1), or within 1e-9 of the
// imaginary axis relative to |s| (of the unit circle); two such poles within 1e-6
// relative are one repeated pole.
// Undecided: the certified enclosure of some pole straddles the boundary and none is
// proven outside (certified_stability.hpp); this list-of-poles verdict never says it.
enum class Stability { Stable, Marginal, Unstable, Undecided };
// "stable", "marginal", "unstable", "undecided" (the JSON reports' words).
const char* to_string(Stability s);
// The verdict above for poles in s (discrete false) or in z (discrete true).
Stability stability(const std::vector<Complex>& poles, bool discrete);
// The verdict of a transfer's poles, those at the boundary point included (hidden modes
// are not its poles: judge Siso::modes() for internal stability).
inline Stability stability(const Zpk& g) { return stability(g.all_poles(), g.is_discrete()); }
// Whether a pole lies on the boundary in the sense above.
bool on_boundary(const Complex& p, bool discrete);

}  // namespace dmbd::blocks
