// System identification of the RFSEA (see sysid.hpp for the model and the experiment).
#include "dmbd/experiments/sysid.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/FFT>
#include <unsupported/Eigen/LevenbergMarquardt>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/frequency.hpp"

namespace dmbd::experiments {

namespace {

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void fail(const std::string& message) { throw InputError(message); }

bool finite(double v) { return std::isfinite(v); }

}  // namespace

// ---------------------------------------------------------------------------------
// Excitation

void ExponentialChirp::validate() const {
  if (!(finite(f0_hz) && finite(f1_hz) && f0_hz > 0 && f1_hz > f0_hz))
    fail(fmt::format("exponential chirp: expected 0 < f0_hz < f1_hz, got f0_hz = {}, f1_hz = {}", f0_hz, f1_hz));
  if (!(finite(duration_s) && duration_s > 0))
    fail(fmt::format("exponential chirp: expected duration_s > 0, got {}", duration_s));
  if (!finite(amplitude)) fail("exponential chirp: amplitude is not finite");
  if (!(fade_in_s >= 0 && fade_out_s >= 0 && fade_in_s + fade_out_s <= duration_s))
    fail(fmt::format("exponential chirp: expected fades >= 0 with fade_in_s + fade_out_s <= duration_s ({}), got {} "
                     "and {}",
                     duration_s, fade_in_s, fade_out_s));
}

double ExponentialChirp::phase_rad(double t_s) const {
  const double t = std::clamp(t_s, 0.0, duration_s);
  const double l = std::log(f1_hz / f0_hz);
  // expm1 keeps the phase accurate for small t (exp(x) - 1 would lose digits).
  return 2.0 * kPi * f0_hz * duration_s / l * std::expm1(t * l / duration_s);
}

double ExponentialChirp::frequency_hz(double t_s) const {
  const double t = std::clamp(t_s, 0.0, duration_s);
  return f0_hz * std::exp(t / duration_s * std::log(f1_hz / f0_hz));
}

double ExponentialChirp::time_at_hz(double f_hz) const {
  return duration_s * std::log(f_hz / f0_hz) / std::log(f1_hz / f0_hz);
}

double ExponentialChirp::value(double t_s) const {
  if (!(t_s >= 0.0 && t_s <= duration_s)) return 0.0;
  double w = 1.0;
  if (fade_in_s > 0 && t_s < fade_in_s) w = 0.5 * (1.0 - std::cos(kPi * t_s / fade_in_s));
  const double to_end = duration_s - t_s;
  if (fade_out_s > 0 && to_end < fade_out_s) w *= 0.5 * (1.0 - std::cos(kPi * to_end / fade_out_s));
  return amplitude * w * std::sin(phase_rad(t_s));
}

std::vector<double> ExponentialChirp::sample(double fs_hz, double lead_in_s, double tail_s) const {
  validate();
  if (!(finite(fs_hz) && fs_hz > 0)) fail(fmt::format("exponential chirp: expected fs_hz > 0, got {}", fs_hz));
  if (!(lead_in_s >= 0 && tail_s >= 0)) fail("exponential chirp: lead-in and tail must be >= 0");
  const auto n = static_cast<std::size_t>(std::llround((lead_in_s + duration_s + tail_s) * fs_hz)) + 1;
  std::vector<double> u(n);
  for (std::size_t k = 0; k < n; ++k) u[k] = value(static_cast<double>(k) / fs_hz - lead_in_s);
  return u;
}

double exponential_chirp(double f0_hz, double f1_hz, double duration_s, double amplitude, double t_s) {
  ExponentialChirp c{f0_hz, f1_hz, duration_s, amplitude};
  c.validate();
  return c.value(t_s);
}

double exponential_chirp_frequency_hz(double f0_hz, double f1_hz, double duration_s, double t_s) {
  ExponentialChirp c{f0_hz, f1_hz, duration_s, 1.0};
  c.validate();
  return c.frequency_hz(t_s);
}

std::vector<double> log_frequencies(double lo_hz, double hi_hz, int n) {
  if (!(lo_hz > 0 && hi_hz >= lo_hz && n >= 1))
    fail(fmt::format("log_frequencies: expected 0 < lo <= hi and n >= 1, got {}, {}, {}", lo_hz, hi_hz, n));
  std::vector<double> f(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    f[static_cast<std::size_t>(k)] = n == 1 ? lo_hz : lo_hz * std::pow(hi_hz / lo_hz, static_cast<double>(k) / (n - 1));
  return f;
}

// ---------------------------------------------------------------------------------
// Frequency-response estimation
//
// Why this estimator. The chirp is a transient: it starts from rest, sweeps once and
// (with the fade-out and a quiet tail) ends at rest. For a linear sampled system that
// starts at rest, the DTFTs of the *whole* input and output records obey Y = H_d U
// exactly at every frequency, as long as the records contain the whole response (the
// end value is continued as a constant, so a free load that ended displaced is fine).
// The DFT of the whole records samples those DTFTs, so a noise-free estimate is exact:
// no leakage, no window bias on a lightly damped resonance. Welch averaging instead
// cuts the sweep into segments that each hold only part of the band and cut through
// transients (bias), and segments that the sweep is not in add only noise.
// With noise, one DFT bin is a single noisy ratio (its "coherence" is identically 1),
// so each estimate uses the bins of a narrow band around the requested frequency
// (relative_bandwidth, 2 % by default: well below the half-power width 2 zeta of the
// actuator's resonances, zeta ~ 0.15) and fits a local polynomial in frequency,
// Y_k = (a + b d + c d^2) U_k: a is the estimate at the centre (the local slope and
// curvature of H across the band do not bias it, as they do a plain H1 average), and
// the fit residual estimates the noise, hence var(a) and the weight. Bins spaced fs/N
// are nearly independent, so the variance falls as 1/(bins) and the band can stay
// narrow for long records (the sweep's energy per bin is the same whatever the record
// length: an exponential chirp of duration T puts |U|^2 ~ T/(f ln(f1/f0)) per Hz).
// Not used: the local polynomial method's transient term (a second polynomial T_k
// added to Y_k to absorb a record that ends unsettled). At the low end of a chirp the
// input spectrum is smooth too (its phase turns by 2 pi t(f)/T per bin, t(f) ~ 0
// there), so T_k and H U_k become nearly collinear: tried, it made the estimates
// near f0 worse by 1e-2, far more than the unsettled tail it was meant to absorb
// (~1e-4 for a free load whose slow mode, tau = (B' + B_l)/K_l ~ 10 s, is still
// decaying 2 s after the sweep).
namespace {

bool five_smooth(std::size_t n) {
  for (std::size_t p : {2, 3, 5})
    while (n % p == 0) n /= p;
  return n == 1;
}

// The N-point DFT X_k = sum_n x_n e^{-j 2 pi k n / N}, k = 0 .. N/2, of a record of
// any length N. Exactly N points (no zero padding) so that the bins are the record's
// own (fs/N apart, nearly independent) and the end-value continuation is exact
// (e^{-j w_k N} = 1 at every bin). kissfft directly when N has only the factors 2, 3, 5; otherwise
// Bluestein's algorithm, k n = (k^2 + n^2 - (k - n)^2) / 2, which turns the DFT into a
// convolution done with power-of-two FFTs (the chirp's transform computed once per
// length).
class Dft {
 public:
  explicit Dft(std::size_t n) : n_(n), smooth_(five_smooth(n)) {
    if (smooth_) return;
    m_ = 1;
    while (m_ < 2 * n - 1) m_ *= 2;
    // w_i = e^{j pi i^2 / N}; i^2 reduced modulo 2N in integers keeps the phase exact.
    w_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto i2 = static_cast<unsigned long long>(i) * i % (2ULL * n);
      w_[i] = std::polar(1.0, kPi * static_cast<double>(i2) / static_cast<double>(n));
    }
    std::vector<Complex> b(m_, 0.0);
    b[0] = w_[0];
    for (std::size_t i = 1; i < n; ++i) b[i] = b[m_ - i] = w_[i];
    fft_.fwd(fb_, b);
  }

  // Bins 0 .. N/2 of the N-point DFT of x (x.size() == N).
  std::vector<Complex> half(const std::vector<double>& x) {
    std::vector<Complex> out;
    if (smooth_) {
      const std::vector<Complex> xc(x.begin(), x.end());
      fft_.fwd(out, xc);
    } else {
      std::vector<Complex> a(m_, 0.0), fa, c;
      for (std::size_t i = 0; i < n_; ++i) a[i] = x[i] * std::conj(w_[i]);
      fft_.fwd(fa, a);
      for (std::size_t i = 0; i < m_; ++i) fa[i] *= fb_[i];
      fft_.inv(c, fa);
      out.resize(n_ / 2 + 1);
      for (std::size_t k = 0; k < out.size(); ++k) out[k] = std::conj(w_[k]) * c[k];
    }
    out.resize(n_ / 2 + 1);
    return out;
  }

 private:
  std::size_t n_, m_ = 0;
  bool smooth_;
  std::vector<Complex> w_, fb_;
  Eigen::FFT<double> fft_;
};

struct Spectrum {
  std::vector<Complex> X;  // bins 0 .. N/2
  double df_hz = 0;
};

double mean_of(const std::vector<double>& x, std::size_t begin, std::size_t end) {
  double s = 0;
  for (std::size_t k = begin; k < end; ++k) s += x[k];
  return s / static_cast<double>(end - begin);
}

Spectrum record_spectrum(Dft& dft, const std::vector<double>& x, double fs_hz, const FrfOptions& o) {
  const std::size_t n = x.size();
  const auto nb = std::clamp<std::size_t>(static_cast<std::size_t>(std::llround(o.baseline_s * fs_hz)), 1, n);
  const auto nt = std::clamp<std::size_t>(static_cast<std::size_t>(std::llround(o.tail_average_s * fs_hz)), 1, n);
  const double base = mean_of(x, 0, nb);
  const double end = mean_of(x, n - nt, n) - base;
  std::vector<double> centred(n);
  for (std::size_t k = 0; k < n; ++k) centred[k] = x[k] - base;
  Spectrum s;
  s.X = dft.half(centred);
  s.df_hz = fs_hz / static_cast<double>(n);
  // The end value continued for ever: sum_{n >= N} end e^{-j w n} = end / (1 - e^{-j w})
  // at every bin (w N is a multiple of 2 pi).
  if (end != 0.0)
    for (std::size_t k = 1; k < s.X.size(); ++k)
      s.X[k] += end / (1.0 - std::polar(1.0, -2.0 * kPi * static_cast<double>(k) / static_cast<double>(n)));
  return s;
}

void check_frf_inputs(const std::vector<double>& u, const std::vector<std::vector<double>>& ys, double fs_hz,
                      const std::vector<double>& f_hz, const FrfOptions& o) {
  if (!(finite(fs_hz) && fs_hz > 0)) fail(fmt::format("frequency response: expected fs_hz > 0, got {}", fs_hz));
  if (u.size() < 16) fail(fmt::format("frequency response: expected at least 16 samples, got {}", u.size()));
  for (std::size_t j = 0; j < ys.size(); ++j)
    if (ys[j].size() != u.size())
      fail(fmt::format("frequency response: output {} has {} samples, the input {}", j, ys[j].size(), u.size()));
  for (double f : f_hz)
    if (!(f > 0 && f < fs_hz / 2))
      fail(fmt::format("frequency response: expected frequencies in (0, {}) Hz, got {}", fs_hz / 2, f));
  if (!(o.relative_bandwidth >= 0 && o.min_bins >= 1 && o.local_order >= 0 && o.local_order <= 2 &&
        o.baseline_s >= 0 && o.tail_average_s >= 0 && o.relative_std_floor >= 0))
    fail("frequency response: expected relative_bandwidth >= 0, min_bins >= 1, local_order 0..2, baseline_s, "
         "tail_average_s, relative_std_floor >= 0");
}

FrequencyResponseEstimate estimate_from_spectra(const Spectrum& su, const Spectrum& sy, const std::vector<double>& f_hz,
                                                const FrfOptions& o) {
  const int p = o.local_order + 1;
  const int min_bins = std::max(o.min_bins, p + 2);  // at least 2 residual degrees of freedom
  const auto last = static_cast<long>(su.X.size()) - 2;  // highest usable bin (below Nyquist)
  if (last < min_bins) fail(fmt::format("frequency response: the record is too short for {} bins", min_bins));
  const double r = 1.0 + o.relative_bandwidth / 2.0;
  FrequencyResponseEstimate e;
  e.f_hz = f_hz;
  for (double f : f_hz) {
    long k0 = static_cast<long>(std::ceil(f / r / su.df_hz));
    long k1 = static_cast<long>(std::floor(f * r / su.df_hz));
    if (k1 - k0 + 1 < min_bins) {
      const long kc = std::lround(f / su.df_hz);
      k0 = kc - (min_bins - 1) / 2;
      k1 = k0 + min_bins - 1;
    }
    if (k0 < 1) {
      k1 += 1 - k0;
      k0 = 1;
    }
    if (k1 > last) {
      k0 -= k1 - last;
      k1 = last;
    }
    k0 = std::max(k0, 1L);
    const long n = k1 - k0 + 1;
    const double half_width = std::max(0.5 * static_cast<double>(n - 1) * su.df_hz, su.df_hz);
    Eigen::MatrixXcd phi(n, p);
    Eigen::VectorXcd y(n);
    double suu = 0, syy = 0;
    Complex syu = 0;
    for (long k = k0; k <= k1; ++k) {
      const Complex U = su.X[static_cast<std::size_t>(k)], Y = sy.X[static_cast<std::size_t>(k)];
      const double d = (static_cast<double>(k) * su.df_hz - f) / half_width;
      for (int j = 0; j < p; ++j) phi(k - k0, j) = U * std::pow(d, j);
      y(k - k0) = Y;
      suu += std::norm(U);
      syy += std::norm(Y);
      syu += Y * std::conj(U);
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXcd> qr(phi);
    const Eigen::VectorXcd theta = qr.solve(y);
    const double rss = (y - phi * theta).squaredNorm();
    const double sigma2 = n > p ? rss / static_cast<double>(n - p) : 0.0;
    // var(a) = sigma^2 [(Phi^H Phi)^-1]_00
    const Eigen::MatrixXcd g = phi.adjoint() * phi;
    const Eigen::MatrixXcd ginv = g.ldlt().solve(Eigen::MatrixXcd::Identity(p, p));
    const Complex H = theta(0);
    const double var_a = sigma2 * std::abs(ginv(0, 0).real());
    const double rel = std::abs(H) > 0 ? std::sqrt(var_a) / std::abs(H) : std::numeric_limits<double>::infinity();
    e.H.push_back(H);
    e.coherence.push_back(suu > 0 && syy > 0 ? std::norm(syu) / (suu * syy) : 0.0);
    e.bins.push_back(static_cast<double>(n));
    e.relative_std.push_back(rel);
    e.weight.push_back(1.0 / std::sqrt(rel * rel + o.relative_std_floor * o.relative_std_floor +
                                       std::numeric_limits<double>::min()));
  }
  return e;
}

}  // namespace

std::vector<FrequencyResponseEstimate> estimate_frequency_responses(const std::vector<double>& u,
                                                                    const std::vector<std::vector<double>>& ys,
                                                                    double fs_hz, const std::vector<double>& f_hz,
                                                                    const FrfOptions& options) {
  check_frf_inputs(u, ys, fs_hz, f_hz, options);
  Dft dft(u.size());
  const Spectrum su = record_spectrum(dft, u, fs_hz, options);
  std::vector<FrequencyResponseEstimate> out;
  out.reserve(ys.size());
  for (const auto& y : ys)
    out.push_back(estimate_from_spectra(su, record_spectrum(dft, y, fs_hz, options), f_hz, options));
  return out;
}

FrequencyResponseEstimate estimate_frequency_response(const std::vector<double>& u, const std::vector<double>& y,
                                                      double fs_hz, const std::vector<double>& f_hz,
                                                      const FrfOptions& options) {
  return estimate_frequency_responses(u, {y}, fs_hz, f_hz, options).front();
}

// ---------------------------------------------------------------------------------
// The RFSEA model

std::array<double, kRfseaNumParams> to_array(const RfseaParams& p) {
  return {p.J_m, p.B_m, p.M_r, p.B_r, p.K_r, p.M_l, p.B_l, p.K_l};
}

RfseaParams from_array(const std::array<double, kRfseaNumParams>& a) {
  return RfseaParams{a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]};
}

const char* rfsea_param_name(int index) {
  static const char* const names[kRfseaNumParams] = {"J_m", "B_m", "M_r", "B_r", "K_r", "M_l", "B_l", "K_l"};
  return index >= 0 && index < kRfseaNumParams ? names[index] : "?";
}

namespace {

void check_model(RfseaTest test, const RfseaParams& p, const RfseaConstants& c) {
  const bool ok = p.J_m > 0 && p.B_m >= 0 && p.M_r > 0 && p.B_r >= 0 && p.K_r > 0 && c.k_tau > 0 && c.N_m > 0 &&
                  c.N_l >= 0 && finite(p.J_m + p.B_m + p.M_r + p.B_r + p.K_r + c.k_tau + c.N_m + c.N_l);
  if (!ok)
    fail(fmt::format("RFSEA model: expected J_m, M_r, K_r, k_tau, N_m > 0 and B_m, B_r, N_l >= 0 (finite), got J_m = "
                     "{}, B_m = {}, M_r = {}, B_r = {}, K_r = {}, k_tau = {}, N_m = {}, N_l = {}",
                     p.J_m, p.B_m, p.M_r, p.B_r, p.K_r, c.k_tau, c.N_m, c.N_l));
  if (test == RfseaTest::Free && !(p.M_l > 0 && p.B_l >= 0 && p.K_l >= 0 && finite(p.M_l + p.B_l + p.K_l)))
    fail(fmt::format("RFSEA model: the free test expects M_l > 0 and B_l, K_l >= 0, got M_l = {}, B_l = {}, K_l = {}",
                     p.M_l, p.B_l, p.K_l));
}

// The continuous responses from the impedances (independent of the state space).
RfseaResponse continuous_response(RfseaTest test, const RfseaParams& p, const RfseaConstants& c,
                                  const std::vector<double>& f_hz) {
  const double Jp = p.J_m * c.N_m * c.N_m, Bp = p.B_m * c.N_m * c.N_m, G = c.k_tau * c.N_m;
  RfseaResponse r;
  for (double f : f_hz) {
    const Complex s(0.0, 2.0 * kPi * f);
    const Complex Zm = (Jp * s + Bp) * s, Zr = (p.M_r * s + p.B_r) * s + p.K_r;
    Complex xr, xl;
    if (test == RfseaTest::Locked) {
      xr = G / (Zm + Zr);
      xl = 0.0;
    } else {
      const Complex Zl = (p.M_l * s + p.B_l) * s + p.K_l;
      const Complex D = Zl * Zr + Zm * (Zl + Zr);
      xr = G * Zl / D;
      xl = G * Zr / D;
    }
    r.F.push_back(p.K_r * xr);
    r.theta_m.push_back(c.N_m * (xl + xr));
    r.q.push_back(c.N_l * xl);
  }
  return r;
}

}  // namespace

blocks::StateSpace rfsea_state_space(RfseaTest test, const RfseaParams& p, const RfseaConstants& c) {
  check_model(test, p, c);
  const double Jp = p.J_m * c.N_m * c.N_m, Bp = p.B_m * c.N_m * c.N_m, G = c.k_tau * c.N_m;
  if (test == RfseaTest::Locked) {
    const double m = Jp + p.M_r;
    blocks::Matrix a(2, 2), b(2, 1), cc(3, 2), d = blocks::Matrix::Zero(3, 1);
    a << 0, 1, -p.K_r / m, -(Bp + p.B_r) / m;
    b << 0, G / m;
    cc << p.K_r, 0, c.N_m, 0, 0, 0;
    return blocks::StateSpace(a, b, cc, d);
  }
  Eigen::Matrix2d M, B, K;
  M << Jp + p.M_l, Jp, Jp, Jp + p.M_r;
  B << Bp + p.B_l, Bp, Bp, Bp + p.B_r;
  K << p.K_l, 0, 0, p.K_r;
  const Eigen::Matrix2d Minv = M.inverse();
  blocks::Matrix a = blocks::Matrix::Zero(4, 4), b = blocks::Matrix::Zero(4, 1), cc = blocks::Matrix::Zero(3, 4),
                 d = blocks::Matrix::Zero(3, 1);
  a.block(0, 2, 2, 2).setIdentity();
  a.block(2, 0, 2, 2) = -Minv * K;
  a.block(2, 2, 2, 2) = -Minv * B;
  b.block(2, 0, 2, 1) = Minv * Eigen::Vector2d(G, G);
  cc(0, 1) = p.K_r;          // F = K_r x_r
  cc(1, 0) = cc(1, 1) = c.N_m;  // theta_m = N_m (x_l + x_r)
  cc(2, 0) = c.N_l;          // q = N_l x_l
  return blocks::StateSpace(a, b, cc, d);
}

RfseaResponse rfsea_response(RfseaTest test, const RfseaParams& p, const RfseaConstants& c,
                             const std::vector<double>& f_hz, const SamplingModel& sampling) {
  check_model(test, p, c);
  if (!(sampling.ts_s >= 0 && finite(sampling.ts_s) && finite(sampling.delay_samples)))
    fail(fmt::format("RFSEA model: expected a sample time >= 0, got {}", sampling.ts_s));
  RfseaResponse r;
  if (sampling.ts_s == 0.0) {
    r = continuous_response(test, p, c, f_hz);
  } else {
    // Exact ZOH equivalent: x[k+1] = A_d x[k] + B_d i[k], y[k] = C x[k].
    const blocks::StateSpace sd = blocks::c2d(rfsea_state_space(test, p, c), sampling.ts_s, blocks::C2dMethod::Zoh);
    std::vector<double> w(f_hz.size());
    for (std::size_t k = 0; k < f_hz.size(); ++k) w[k] = 2.0 * kPi * f_hz[k];
    const auto h = blocks::frequency_response(sd, w);
    for (const auto& m : h) {
      r.F.push_back(m(0, 0));
      r.theta_m.push_back(m(1, 0));
      r.q.push_back(m(2, 0));
    }
  }
  if (sampling.delay_samples != 0.0)
    for (std::size_t k = 0; k < f_hz.size(); ++k) {
      const Complex z = std::polar(1.0, -2.0 * kPi * f_hz[k] * sampling.ts_s * sampling.delay_samples);
      r.F[k] *= z;
      r.theta_m[k] *= z;
      r.q[k] *= z;
    }
  return r;
}

double rfsea_free_test_max_amplitude(const RfseaParams& p, const RfseaConstants& c, double f0_hz, double f1_hz,
                                     double q_max_rad) {
  if (!(f0_hz > 0 && f1_hz >= f0_hz && q_max_rad > 0 && c.N_l > 0))
    fail("rfsea_free_test_max_amplitude: expected 0 < f0 <= f1, q_max > 0 and N_l > 0");
  const auto r = continuous_response(RfseaTest::Free, p, c, log_frequencies(f0_hz, f1_hz, 400));
  double peak = 0;
  for (const auto& q : r.q) peak = std::max(peak, std::abs(q));
  return q_max_rad / peak;
}

RfseaTestData rfsea_test_data(const RfseaRecord& record, double fs_hz, const std::vector<double>& f_hz,
                              const FrfOptions& options) {
  std::vector<std::vector<double>> ys{record.F, record.theta_m};
  if (!record.q.empty()) ys.push_back(record.q);
  const auto e = estimate_frequency_responses(record.i, ys, fs_hz, f_hz, options);
  RfseaTestData d;
  d.f_hz = f_hz;
  d.F = {e[0].H, e[0].weight};
  d.theta_m = {e[1].H, e[1].weight};
  if (e.size() > 2) d.q = {e[2].H, e[2].weight};
  return d;
}

// ---------------------------------------------------------------------------------
// Identification

namespace {

bool has(const RfseaChannel& ch) { return !ch.H.empty(); }
bool has(const RfseaTestData& t) { return !t.f_hz.empty(); }

void check_test(const RfseaTestData& t, const char* name, double nyquist_hz) {
  if (!has(t)) return;
  for (double f : t.f_hz)
    if (!(f > 0 && f < nyquist_hz))
      fail(fmt::format("RFSEA sysid: {} test frequency {} Hz outside (0, {}) Hz", name, f, nyquist_hz));
  const std::pair<const RfseaChannel*, const char*> chans[] = {{&t.F, "F"}, {&t.theta_m, "theta_m"}, {&t.q, "q"}};
  int used = 0;
  for (const auto& [ch, cname] : chans) {
    if (!has(*ch)) continue;
    ++used;
    if (ch->H.size() != t.f_hz.size())
      fail(fmt::format("RFSEA sysid: {} test channel {} has {} values for {} frequencies", name, cname, ch->H.size(),
                       t.f_hz.size()));
    if (!ch->weight.empty() && ch->weight.size() != t.f_hz.size())
      fail(fmt::format("RFSEA sysid: {} test channel {} has {} weights for {} frequencies", name, cname,
                       ch->weight.size(), t.f_hz.size()));
    for (std::size_t k = 0; k < ch->H.size(); ++k)
      if (!(std::isfinite(ch->H[k].real()) && std::isfinite(ch->H[k].imag()) && std::abs(ch->H[k]) > 0) ||
          (!ch->weight.empty() && !(ch->weight[k] >= 0 && finite(ch->weight[k]))))
        fail(fmt::format("RFSEA sysid: {} test channel {} value {} at {} Hz is zero or not finite (or its weight)",
                         name, cname, k, t.f_hz[k]));
  }
  if (used == 0) fail(fmt::format("RFSEA sysid: the {} test has frequencies but no channel", name));
}

double weight_at(const RfseaChannel& ch, std::size_t k) { return ch.weight.empty() ? 1.0 : ch.weight[k]; }

// The hold's effect to first order, (1 - e^{-j w ts}) / (j w ts) e^{-j w ts delay}:
// dividing a measured response by it gives the continuous one up to aliasing (a
// fraction of a percent below fs/10 for these relative-degree-2 responses).
Complex hold(const SamplingModel& s, double f_hz) {
  if (s.ts_s == 0.0) return 1.0;
  const double wt = 2.0 * kPi * f_hz * s.ts_s;
  return (1.0 - std::polar(1.0, -wt)) / Complex(0.0, wt) * std::polar(1.0, -wt * s.delay_samples);
}

double weighted_median(std::vector<std::pair<double, double>> vw) {
  std::sort(vw.begin(), vw.end());
  double total = 0;
  for (const auto& [v, w] : vw) total += w;
  double acc = 0;
  for (const auto& [v, w] : vw) {
    acc += w;
    if (acc >= 0.5 * total) return v;
  }
  return vw.back().first;
}

// Real least squares on stacked complex equations sum_j a_j x_j = rhs (row weights
// applied), columns scaled to unit norm for conditioning.
Eigen::VectorXd complex_lsq(const std::vector<std::vector<Complex>>& cols, const std::vector<Complex>& rhs,
                            const std::vector<double>& w) {
  const auto n = static_cast<Eigen::Index>(cols.size());
  const auto m = static_cast<Eigen::Index>(rhs.size());
  Eigen::MatrixXd a(2 * m, n);
  Eigen::VectorXd b(2 * m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    for (Eigen::Index j = 0; j < n; ++j) {
      const Complex v = w[iu] * cols[static_cast<std::size_t>(j)][iu];
      a(2 * i, j) = v.real();
      a(2 * i + 1, j) = v.imag();
    }
    b(2 * i) = w[iu] * rhs[iu].real();
    b(2 * i + 1) = w[iu] * rhs[iu].imag();
  }
  Eigen::VectorXd scale = a.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < n; ++j)
    if (scale(j) == 0) scale(j) = 1;
  const Eigen::MatrixXd as = a * scale.cwiseInverse().asDiagonal();
  Eigen::VectorXd x = as.colPivHouseholderQr().solve(b);
  return x.cwiseQuotient(scale);
}

}  // namespace

RfseaParams rfsea_initial_guess(const RfseaSysidData& data, const std::array<bool, kRfseaNumParams>& fixed,
                                const RfseaParams& fixed_values) {
  const auto& L = data.locked;
  const auto& Fr = data.free;
  if (!has(L) || !has(L.F) || !has(L.theta_m))
    fail("RFSEA sysid: the initial guess needs the locked test's F and theta_m (K_r = N_m F/theta_m); give "
         "RfseaFitOptions::initial otherwise");
  const RfseaConstants& c = data.constants;
  const double G = c.k_tau * c.N_m, N2 = c.N_m * c.N_m;
  RfseaParams g = fixed_values;

  // K_r: the locked F/theta_m is K_r / N_m at every frequency.
  if (!fixed[kK_r]) {
    std::vector<std::pair<double, double>> vw;
    for (std::size_t k = 0; k < L.f_hz.size(); ++k)
      vw.emplace_back(c.N_m * std::abs(L.F.H[k] / L.theta_m.H[k]),
                      std::min(weight_at(L.F, k), weight_at(L.theta_m, k)));
    g.K_r = weighted_median(vw);
  }

  // Motor equations, per ampere (X_r = F / K_r, Theta = theta_m / N_m, continuous):
  //   J' s^2 Theta + B' s Theta + M_r s^2 X_r + B_r s X_r = G - K_r X_r.
  // Locked rows have Theta = X_r (only the sums J'+M_r, B'+B_r enter); free rows
  // separate them.
  std::vector<std::vector<Complex>> cols(4);
  std::vector<Complex> rhs;
  std::vector<double> w;
  auto add_rows = [&](const RfseaTestData& t, bool locked) {
    for (std::size_t k = 0; k < t.f_hz.size(); ++k) {
      const Complex s(0.0, 2.0 * kPi * t.f_hz[k]);
      const Complex h = hold(data.sampling, t.f_hz[k]);
      const Complex xr = t.F.H[k] / h / g.K_r;
      const Complex th = locked ? xr : t.theta_m.H[k] / h / c.N_m;
      const Complex a[4] = {N2 * s * s * th, N2 * s * th, s * s * xr, s * xr};
      Complex r = G - g.K_r * xr;
      const double v[4] = {g.J_m, g.B_m, g.M_r, g.B_r};
      for (int j = 0; j < 4; ++j) {
        if (fixed[j]) r -= a[j] * v[j];
        cols[static_cast<std::size_t>(j)].push_back(fixed[j] ? 0.0 : a[j]);
      }
      rhs.push_back(r);
      w.push_back(std::min(weight_at(t.F, k), weight_at(t.theta_m, k)) / (std::abs(G) + std::abs(g.K_r * xr)));
    }
  };
  add_rows(L, true);
  const bool free_test = has(Fr) && has(Fr.F) && (has(Fr.theta_m) || (has(Fr.q) && c.N_l > 0));
  if (free_test && has(Fr.theta_m)) add_rows(Fr, false);
  {
    // With only locked rows, J' and M_r (B' and B_r) are one column: fit the sum and
    // split it later.
    const bool split = !(free_test && has(Fr.theta_m));
    std::vector<std::vector<Complex>> cc = cols;
    if (split) {
      for (int j : {0, 1}) {
        const auto jj = static_cast<std::size_t>(j);
        if (!fixed[j] && !fixed[j + 2]) {
          // column for the sum in units of the elastomer's (kg, N s/m)
          for (std::size_t i = 0; i < cc[jj].size(); ++i) cc[jj][i] = cc[jj + 2][i];
          for (auto& v : cc[jj + 2]) v = 0.0;
        }
      }
    }
    const Eigen::VectorXd x = complex_lsq(cc, rhs, w);
    const double given[4] = {g.J_m, g.B_m, g.M_r, g.B_r};
    double v[4];
    for (int j = 0; j < 4; ++j) v[j] = fixed[j] ? given[j] : x(j);
    for (int j : {0, 1}) {
      if (split && !fixed[j] && !fixed[j + 2]) {
        // Only the sum is known (in kg or N s/m): put a small share on the elastomer.
        const double sum = std::abs(x(j));
        v[j] = 0.99 * sum / N2;
        v[j + 2] = 0.01 * sum;
      }
      // Keep the fitted values positive (noise, or a fixed partner larger than the
      // sum, can push one below zero): at least 1e-3 of the pair's size.
      const double ref = std::abs(v[j] * N2) + std::abs(v[j + 2]);
      if (!fixed[j] && !(v[j] * N2 > 1e-3 * ref)) v[j] = 1e-3 * ref / N2;
      if (!fixed[j + 2] && !(v[j + 2] > 1e-3 * ref)) v[j + 2] = 1e-3 * ref;
    }
    if (!fixed[kJ_m]) g.J_m = v[0];
    if (!fixed[kB_m]) g.B_m = v[1];
    if (!fixed[kM_r]) g.M_r = v[2];
    if (!fixed[kB_r]) g.B_r = v[3];
  }

  // Load equation: (M_l s^2 + B_l s + K_l) X_l = Z_r X_r, X_l = Theta - X_r (or q/N_l).
  if (free_test) {
    std::vector<std::vector<Complex>> lc(3);
    std::vector<Complex> lr;
    std::vector<double> lw;
    double wmin = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < Fr.f_hz.size(); ++k) {
      const Complex s(0.0, 2.0 * kPi * Fr.f_hz[k]);
      const Complex h = hold(data.sampling, Fr.f_hz[k]);
      const Complex xr = Fr.F.H[k] / h / g.K_r;
      const Complex xl = has(Fr.theta_m) ? Fr.theta_m.H[k] / h / c.N_m - xr : Fr.q.H[k] / h / c.N_l;
      const Complex fs = ((g.M_r * s + g.B_r) * s + g.K_r) * xr;
      const Complex a[3] = {s * s * xl, s * xl, xl};
      const double v[3] = {g.M_l, g.B_l, g.K_l};
      Complex r = fs;
      for (int j = 0; j < 3; ++j) {
        if (fixed[kM_l + j]) r -= a[j] * v[j];
        lc[static_cast<std::size_t>(j)].push_back(fixed[kM_l + j] ? 0.0 : a[j]);
      }
      lr.push_back(r);
      lw.push_back(std::min(weight_at(Fr.F, k), has(Fr.theta_m) ? weight_at(Fr.theta_m, k) : weight_at(Fr.q, k)) /
                   std::abs(fs));
      wmin = std::min(wmin, 2.0 * kPi * Fr.f_hz[k]);
    }
    const Eigen::VectorXd x = complex_lsq(lc, lr, lw);
    if (!fixed[kM_l]) g.M_l = x(0);
    if (!fixed[kB_l]) g.B_l = x(1);
    if (!fixed[kK_l]) g.K_l = x(2);
    // Keep them positive for the log-parameter fit: a value the data barely see
    // (K_l well below the band's |Z_l|) can come out negative.
    const double zl = std::abs(Complex(-std::abs(g.M_l) * wmin * wmin, std::abs(g.B_l) * wmin));
    if (!fixed[kM_l] && !(g.M_l > 0)) g.M_l = std::max(std::abs(g.M_l), 1e-3);
    if (!fixed[kB_l] && !(g.B_l > 0)) g.B_l = std::max(std::abs(g.B_l), 1e-3);
    if (!fixed[kK_l] && !(g.K_l > 0.01 * zl)) g.K_l = 0.01 * zl;
  }
  return g;
}

namespace {

// The residual of the fit as a functor for Eigen's Levenberg-Marquardt.
struct RfseaResidual : Eigen::DenseFunctor<double> {
  const RfseaSysidData* data;
  std::array<double, kRfseaNumParams> base{};  // values of the fixed parameters
  std::vector<int> free_index;                 // fit variable j -> parameter index
  int evaluations = 0;

  RfseaResidual(const RfseaSysidData& d, const std::array<double, kRfseaNumParams>& b, std::vector<int> idx, int m)
      : Eigen::DenseFunctor<double>(static_cast<int>(idx.size()), m), data(&d), base(b), free_index(std::move(idx)) {}

  // Parameters from log-parameters, each kept within a factor e^20 (5e8) of its
  // starting value: a wild trial step must not overflow the model.
  RfseaParams params(const Eigen::VectorXd& x) const {
    auto a = base;
    for (std::size_t j = 0; j < free_index.size(); ++j) {
      const auto i = static_cast<std::size_t>(free_index[j]);
      const double x0 = std::log(base[i]);
      a[i] = std::exp(std::clamp(x(static_cast<Eigen::Index>(j)), x0 - 20.0, x0 + 20.0));
    }
    return from_array(a);
  }

  // Residuals r = w log(H_meas / H_model), weighted (or not).
  void residual(const Eigen::VectorXd& x, Eigen::VectorXd& r, bool weighted) const {
    const RfseaParams p = params(x);
    Eigen::Index i = 0;
    auto one = [&](RfseaTest test, const RfseaTestData& t) {
      if (!has(t)) return;
      RfseaResponse m;
      try {
        m = rfsea_response(test, p, data->constants, t.f_hz, data->sampling);
      } catch (const InputError&) {
        // A trial step so far out that the model is not finite: a large residual
        // makes Levenberg-Marquardt shrink the step.
        r.setConstant(1e6);
        i = r.size();
        return;
      }
      const std::pair<const RfseaChannel*, const std::vector<Complex>*> chans[] = {
          {&t.F, &m.F}, {&t.theta_m, &m.theta_m}, {&t.q, &m.q}};
      for (const auto& [ch, model] : chans) {
        if (!has(*ch)) continue;
        for (std::size_t k = 0; k < t.f_hz.size(); ++k) {
          const Complex e = std::log(ch->H[k] / (*model)[k]);
          const double w = weighted ? weight_at(*ch, k) : 1.0;
          r(i++) = w * e.real();
          r(i++) = w * e.imag();
        }
      }
    };
    one(RfseaTest::Locked, data->locked);
    if (i < r.size()) one(RfseaTest::Free, data->free);
    for (Eigen::Index k = 0; k < r.size(); ++k)
      if (!std::isfinite(r(k))) r(k) = 1e6;
  }

  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    ++evaluations;
    residual(x, r, true);
    return 0;
  }

  // Central differences in log-parameters (a relative step of 1e-6: the residuals are
  // smooth and computed to ~1e-13).
  int df(const Eigen::VectorXd& x, Eigen::MatrixXd& jac) {
    const double h = 1e-6;
    Eigen::VectorXd rp(values()), rm(values());
    jac.resize(values(), inputs());
    for (Eigen::Index j = 0; j < x.size(); ++j) {
      Eigen::VectorXd xp = x, xm = x;
      xp(j) += h;
      xm(j) -= h;
      (*this)(xp, rp);
      (*this)(xm, rm);
      jac.col(j) = (rp - rm) / (2 * h);
    }
    return static_cast<int>(2 * x.size());
  }
};

}  // namespace

RfseaFit identify_rfsea(const RfseaSysidData& data, const RfseaFitOptions& options) {
  if (!(data.sampling.ts_s >= 0 && finite(data.sampling.ts_s)))
    fail(fmt::format("RFSEA sysid: expected a sample time >= 0, got {}", data.sampling.ts_s));
  const double nyquist = data.sampling.ts_s > 0 ? 0.5 / data.sampling.ts_s : std::numeric_limits<double>::infinity();
  check_test(data.locked, "locked", nyquist);
  check_test(data.free, "free", nyquist);
  if (!has(data.locked) && !has(data.free)) fail("RFSEA sysid: no test data (locked and free are both empty)");
  if (has(data.free.q) && !(data.constants.N_l > 0))
    fail("RFSEA sysid: the free test has a q channel but constants.N_l is not > 0");

  auto fixed = options.fixed;
  if (!has(data.free)) {
    // The load does not enter the locked test.
    fixed[kM_l] = fixed[kB_l] = fixed[kK_l] = true;
    if (!fixed[kJ_m] && !fixed[kM_r])
      fail("RFSEA sysid: the locked test alone gives J_m N_m^2 + M_r only: fix J_m or M_r (RfseaFitOptions::fixed)");
    if (!fixed[kB_m] && !fixed[kB_r])
      fail("RFSEA sysid: the locked test alone gives B_m N_m^2 + B_r only: fix B_m or B_r (RfseaFitOptions::fixed)");
  }
  RfseaParams initial = options.initial ? *options.initial : rfsea_initial_guess(data, fixed, options.fixed_values);
  {
    // Fixed parameters take fixed_values.
    auto a = to_array(initial);
    const auto fv = to_array(options.fixed_values);
    for (int j = 0; j < kRfseaNumParams; ++j)
      if (fixed[static_cast<std::size_t>(j)]) a[static_cast<std::size_t>(j)] = fv[static_cast<std::size_t>(j)];
    initial = from_array(a);
  }
  const auto init = to_array(initial);
  std::vector<int> free_index;
  for (int j = 0; j < kRfseaNumParams; ++j) {
    if (fixed[static_cast<std::size_t>(j)]) continue;
    if (!(init[static_cast<std::size_t>(j)] > 0 && finite(init[static_cast<std::size_t>(j)])))
      fail(fmt::format("RFSEA sysid: the initial {} = {} must be > 0 to be fitted (fix it otherwise)",
                       rfsea_param_name(j), init[static_cast<std::size_t>(j)]));
    free_index.push_back(j);
  }
  if (free_index.empty()) fail("RFSEA sysid: every parameter is fixed");

  int m = 0;
  for (const RfseaTestData* t : {&data.locked, &data.free})
    for (const RfseaChannel* ch : {&t->F, &t->theta_m, &t->q})
      if (has(*t) && has(*ch)) m += 2 * static_cast<int>(t->f_hz.size());
  if (m < static_cast<int>(free_index.size()))
    fail(fmt::format("RFSEA sysid: {} residuals for {} parameters", m, free_index.size()));

  RfseaFit fit;
  fit.initial = initial;
  using S = Eigen::LevenbergMarquardtSpace::Status;
  // Two stages. M_r is 0.2 % of the moving mass (J' ~ 704 kg): the data fix it only
  // once everything else is close, and from a poor start the first large steps can
  // push log M_r onto the plateau M_r -> 0 where its gradient vanishes (seen with
  // starts 1.5x off). So the first stage holds M_r at its initial value and the
  // second frees it from the first stage's solution.
  std::vector<std::vector<int>> stages;
  if (std::find(free_index.begin(), free_index.end(), static_cast<int>(kM_r)) != free_index.end() &&
      free_index.size() > 1) {
    std::vector<int> first;
    for (int j : free_index)
      if (j != kM_r) first.push_back(j);
    stages.push_back(first);
  }
  stages.push_back(free_index);
  auto current = init;
  S status = S::NotStarted;
  for (const auto& idx : stages) {
    RfseaResidual stage(data, current, idx, m);
    Eigen::VectorXd xs(static_cast<Eigen::Index>(idx.size()));
    for (std::size_t j = 0; j < idx.size(); ++j)
      xs(static_cast<Eigen::Index>(j)) = std::log(current[static_cast<std::size_t>(idx[j])]);
    Eigen::LevenbergMarquardt<RfseaResidual> lm(stage);
    lm.setMaxfev(std::max(options.max_evaluations - fit.evaluations, 1));
    lm.setXtol(1e-12);
    lm.setFtol(1e-14);
    lm.setGtol(0.0);
    status = lm.minimize(xs);
    current = to_array(stage.params(xs));
    fit.iterations += static_cast<int>(lm.iterations());
    fit.evaluations += stage.evaluations;
  }

  RfseaResidual fn(data, current, free_index, m);
  Eigen::VectorXd x(static_cast<Eigen::Index>(free_index.size()));
  for (std::size_t j = 0; j < free_index.size(); ++j)
    x(static_cast<Eigen::Index>(j)) = std::log(current[static_cast<std::size_t>(free_index[j])]);
  fit.params = from_array(current);
  fit.converged = status == S::RelativeReductionTooSmall || status == S::RelativeErrorTooSmall ||
                  status == S::RelativeErrorAndReductionTooSmall || status == S::CosinusTooSmall ||
                  status == S::FtolTooSmall || status == S::XtolTooSmall || status == S::GtolTooSmall;
  switch (status) {
    case S::RelativeReductionTooSmall: fit.status = "converged: relative reduction below ftol"; break;
    case S::RelativeErrorTooSmall: fit.status = "converged: relative step below xtol"; break;
    case S::RelativeErrorAndReductionTooSmall: fit.status = "converged: step and reduction below tolerance"; break;
    case S::CosinusTooSmall: fit.status = "converged: residual orthogonal to the Jacobian"; break;
    case S::TooManyFunctionEvaluation: fit.status = "stopped: too many function evaluations"; break;
    case S::FtolTooSmall: fit.status = "converged: no further reduction possible (ftol)"; break;
    case S::XtolTooSmall: fit.status = "converged: no further step possible (xtol)"; break;
    case S::GtolTooSmall: fit.status = "converged: gradient orthogonal (gtol)"; break;
    default: fit.status = fmt::format("failed: Levenberg-Marquardt status {}", static_cast<int>(status)); break;
  }

  Eigen::VectorXd r(m), ru(m);
  fn.residual(x, r, true);
  fn.residual(x, ru, false);
  fit.rms_residual = std::sqrt(r.squaredNorm() / m);
  fit.rms_log_error = std::sqrt(ru.squaredNorm() / m);
  {
    Eigen::MatrixXd jac;
    fn.df(x, jac);
    const auto n = static_cast<int>(free_index.size());
    const double s2 = m > n ? r.squaredNorm() / (m - n) : 0.0;
    const Eigen::MatrixXd jtj = jac.transpose() * jac;
    const Eigen::MatrixXd cov = s2 * jtj.completeOrthogonalDecomposition().pseudoInverse();
    for (int j = 0; j < n; ++j)
      fit.relative_std[static_cast<std::size_t>(free_index[static_cast<std::size_t>(j)])] = std::sqrt(std::max(cov(j, j), 0.0));
  }
  return fit;
}

}  // namespace dmbd::experiments
