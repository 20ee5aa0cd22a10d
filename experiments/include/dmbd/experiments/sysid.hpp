#pragma once
// System identification of DRACO's series-elastic actuators (paper Fig. 5a).
//
// The experiment: an exponential chirp of motor current drives the knee RFSEA of the
// robot twice, once with the output locked and once free; the controller samples the
// current i (the input), the elastomer force F = K_r x_r, the motor angle theta_m and,
// in the free test, the joint angle q. From those records this unit
//   1. makes the excitation (ExponentialChirp),
//   2. estimates frequency responses at chosen frequencies with a quality measure
//      (estimate_frequency_response),
//   3. fits the actuator model of docs/paper-actuators.md section 1 to both tests and
//      all channels at once (identify_rfsea), and gives the model's responses for any
//      parameters (rfsea_response) to draw it over the measurement.
//
// The model (N_m in rad of motor per metre of screw travel, G = k_tau N_m in N/A):
//   J' = J_m N_m^2, B' = B_m N_m^2,  Z_m = J' s^2 + B' s,
//   Z_r = M_r s^2 + B_r s + K_r,     Z_l = M_l s^2 + B_l s + K_l,
//   Z_m (X_l + X_r) = G I - F_s,  Z_l X_l = F_s,  Z_r X_r = F_s,
//   F = K_r X_r,  theta_m = N_m (X_l + X_r),  q = N_l X_l.
// Locked (X_l = 0):  X_r = G I / (Z_m + Z_r).
// Free:              X_r = G Z_l I / D,  X_l = G Z_r I / D,
//                    D = Z_l Z_r + Z_m (Z_l + Z_r).
// Identifiability: the locked test gives K_r (F / theta_m = K_r / N_m), J' + M_r and
// B' + B_r only; the free test separates the rotor from the elastomer and gives the load.
// M_r is the weakest parameter (0.2 % of the mass on the elastomer): with 2 N force
// noise and the 8192-count motor encoder it comes out to ~1 % rms, the rest to 0.1 %.
// q adds nothing that F and theta_m do not carry (x_l = theta_m/N_m - F/K_r, read by
// the encoder far more finely than by a potentiometer): leave it out rather than
// feed it a filtered potentiometer signal whose filter is not divided out.
//
// Experiment design (numbers from tests/sim/test_sysid_identify.cpp, Table I knee):
//   - Each test has its own band and chirp (RfseaTestData::f_hz per test).
//   - Locked: the band can start anywhere (0.01 Hz as in the paper needs minutes of
//     record; 1 Hz is enough: below the 18.5 Hz resonance the response is flat);
//     4 A keeps the resonant force near 3.9 kN.
//   - Free: a free load integrates force, so the lowest frequency sets the current:
//     rfsea_free_test_max_amplitude gives, for |q| < 0.2 rad with M_l = 150 kg,
//     0.118 A from 0.01 Hz, 0.62 A from 0.1 Hz, 1.8 A from 0.3 Hz, 3.05 A from 0.5 Hz,
//     6.2 A from 1 Hz. Mind the elastomer encoder's 1 um step (9.5 N): at 2.5 A from
//     0.5 Hz, M_r came out 19 % off with the sensor noise on; the shipped sysid_knee.yaml
//     runs 2 .. 200 Hz at 10 A (joint swing 0.12 rad), M_r within 0.4 % with noise.
//   - Records: a quiet lead-in (FrfOptions::baseline_s) and a quiet tail for the
//     response to settle; set SamplingModel::ts_s to the controller period.
#include <array>
#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "dmbd/blocks/error.hpp"  // InputError, thrown for user mistakes
#include "dmbd/blocks/state_space.hpp"

namespace dmbd::experiments {

using Complex = std::complex<double>;  // frequency responses (H) and their model values

// ---------------------------------------------------------------------------------
// Excitation

// Exponential (logarithmic) sine sweep from f0_hz to f1_hz over duration_s:
//   u(t) = amplitude * w(t) * sin(phi(t)),
//   phi(t) = 2 pi f0 T / ln(f1/f0) * (exp(t ln(f1/f0) / T) - 1),
//   f(t) = phi'(t) / (2 pi) = f0 (f1/f0)^(t/T),
// with w(t) a raised-cosine fade-in over [0, fade_in_s] and fade-out over
// [T - fade_out_s, T] (1 elsewhere), and u = 0 outside [0, T]. A fade-in of about one
// period of f0 keeps a free load from drifting (the first half cycle of an untapered
// sine is a net impulse); a fade-out lets the record end at rest.
struct ExponentialChirp {
  double f0_hz = 1.0;        // f0, the start frequency, Hz
  double f1_hz = 200.0;      // f1, the end frequency, Hz (> f0)
  double duration_s = 20.0;  // T, the sweep's length, s
  double amplitude = 1.0;    // peak of u, in u's unit (A for a current chirp)
  double fade_in_s = 0.0;    // the raised-cosine fade-in's length, s (0: none)
  double fade_out_s = 0.0;   // the raised-cosine fade-out's length, s (0: none)

  // InputError unless 0 < f0 < f1, duration > 0 and the fades fit in the duration.
  void validate() const;
  double value(double t_s) const;         // u(t), t from the sweep's start (0 outside [0, T]); not validated
  double phase_rad(double t_s) const;     // phi(t), t clamped to [0, T]
  double frequency_hz(double t_s) const;  // f(t), t clamped to [0, T]
  double time_at_hz(double f_hz) const;   // inverse of f(t): T ln(f/f0) / ln(f1/f0)
  // Samples u[k] = value(k / fs - lead_in_s), k = 0 .. round((lead_in + T + tail) fs):
  // a quiet lead-in (for the estimator's baseline) and a quiet tail (for the response
  // to settle) around the sweep.
  std::vector<double> sample(double fs_hz, double lead_in_s = 0.0, double tail_s = 0.0) const;
};

// The same as free functions (no fades): u(t). InputError as validate().
double exponential_chirp(double f0_hz, double f1_hz, double duration_s, double amplitude, double t_s);
// f(t), t clamped to [0, T]. InputError as validate().
double exponential_chirp_frequency_hz(double f0_hz, double f1_hz, double duration_s, double t_s);

// ---------------------------------------------------------------------------------
// Frequency-response estimation
//
// Method (sysid.cpp explains the choice): the DFT of the whole records (exactly N
// points, the end value continued as a constant), and at each requested frequency f
// a local polynomial model Y_k = (a + b d_k + c d_k^2) U_k fitted over the DFT bins
// of a narrow band around f (d_k = f_k - f). The estimate is a = H(f); the residual
// of the local fit measures the noise, hence var(a) and the weight. Exact for
// noise-free records that start at rest and end settled (at rest or at an offset).
struct FrfOptions {
  // Each estimate uses the DFT bins in [f / r, f r], r = 1 + relative_bandwidth / 2,
  // widened to at least min_bins bins (bins are fs / N apart, N the record length).
  double relative_bandwidth = 0.02;
  int min_bins = 7;     // at least this many bins per estimate (and local_order + 3)
  int local_order = 2;  // 0: plain H1 average over the band; 1, 2: local polynomial in f
  // Mean of the first baseline_s of u and of y subtracted (0: the first sample).
  double baseline_s = 0.0;
  // The end value, the mean of the last tail_average_s (0: the last sample), is taken
  // to continue for ever (so a response that settles at an offset, e.g. a free load
  // that moved, is still exact).
  double tail_average_s = 0.0;
  // Floor on the relative standard deviation used for the weight: models and
  // estimates are not better than this (1e-4: 0.001 dB, 0.006 deg).
  double relative_std_floor = 1e-4;
};

// One output's estimate against the input, one entry per requested frequency in every
// vector.
struct FrequencyResponseEstimate {
  std::vector<double> f_hz;           // the requested frequencies, as given, Hz
  std::vector<Complex> H;             // y/u at f_hz
  std::vector<double> coherence;      // band-averaged magnitude-squared coherence, 0..1
  std::vector<double> bins;           // DFT bins used (roughly independent)
  std::vector<double> relative_std;   // std(H)/|H| from the local fit's residual (no floor)
  std::vector<double> weight;         // 1 / sqrt(relative_std^2 + floor^2): ~1/std(log H)
};

// u, y: samples at fs_hz (same length >= 16); f_hz: frequencies within (0, fs/2).
// InputError otherwise, for options out of range (relative_bandwidth, baseline_s,
// tail_average_s, relative_std_floor >= 0, min_bins >= 1, local_order 0..2) and for a
// record too short for min_bins bins. A band that reaches 0 or fs/2 is clipped.
FrequencyResponseEstimate estimate_frequency_response(const std::vector<double>& u, const std::vector<double>& y,
                                                      double fs_hz, const std::vector<double>& f_hz,
                                                      const FrfOptions& options = {});
// Several outputs against one input (the DFT of u computed once).
std::vector<FrequencyResponseEstimate> estimate_frequency_responses(const std::vector<double>& u,
                                                                    const std::vector<std::vector<double>>& ys,
                                                                    double fs_hz, const std::vector<double>& f_hz,
                                                                    const FrfOptions& options = {});

// n log-spaced frequencies from lo to hi inclusive (Hz). InputError unless
// 0 < lo <= hi and n >= 1.
std::vector<double> log_frequencies(double lo_hz, double hi_hz, int n);

// ---------------------------------------------------------------------------------
// The RFSEA model

// Unknowns (paper Table I symbols; the load only matters in the free test).
struct RfseaParams {
  double J_m = 1.6e-5;  // rotor inertia, kg m^2
  double B_m = 2.0e-4;  // rotor damping, N m s/rad
  double M_r = 1.3;     // elastomer / housing mass, kg
  double B_r = 1.6e4;   // elastomer damping, N s/m
  double K_r = 9.5e6;   // elastomer stiffness, N/m
  double M_l = 2953;    // reflected load mass, kg
  double B_l = 2.0e4;   // load damping, N s/m
  double K_l = 0.0;     // load stiffness (gravity through the linkage), N/m
};
constexpr int kRfseaNumParams = 8;  // how many parameters RfseaParams holds (the arrays' length)
// Index order of the fit: J_m, B_m, M_r, B_r, K_r, M_l, B_l, K_l.
enum RfseaParam { kJ_m = 0, kB_m, kM_r, kB_r, kK_r, kM_l, kB_l, kK_l };
// The parameters in RfseaParam order.
std::array<double, kRfseaNumParams> to_array(const RfseaParams& p);
// The inverse of to_array.
RfseaParams from_array(const std::array<double, kRfseaNumParams>& a);
const char* rfsea_param_name(int index);  // "J_m", ... in RfseaParam order; "?" outside 0..7

// Known constants.
struct RfseaConstants {
  double k_tau = 0.0448;  // motor torque constant, N m/A
  double N_m = 6632;      // motor rad per m of screw travel
  double N_l = 20;        // joint rad per m of actuator travel (q = N_l x_l); 0: no q
};

// How the sampled measurement relates to the continuous plant.
struct SamplingModel {
  // 0: the continuous response H(j 2 pi f). > 0: the controller's current is held
  // (zero-order hold) and the outputs sampled every ts_s: the exact ZOH equivalent,
  // H_d(e^{j 2 pi f ts}), which is what a record at that rate measures (at 200 Hz and
  // 2 kHz it lags H(j w) by 18 deg: half a sample).
  double ts_s = 0.0;
  double delay_samples = 0.0;  // extra input delay, samples (e^{-j w ts delay})
};

// The two tests: the actuator's output locked (X_l = 0: the load does not enter), or
// free, moving its load (M_l, B_l, K_l).
enum class RfseaTest { Locked, Free };

// Per ampere: F in N/A, theta_m and q in rad/A (q all zero in the locked test or when
// N_l == 0).
struct RfseaResponse {
  std::vector<Complex> F,  // the elastomer force, N/A, one per frequency
      theta_m,             // the motor angle, rad/A
      q;                   // the joint angle, rad/A
};
// The model's responses at f_hz (Hz): continuous with sampling.ts_s == 0, else the
// exact ZOH equivalent; times e^{-j w ts delay_samples}. InputError for a parameter out
// of range (J_m, M_r, K_r, k_tau, N_m > 0; B_m, B_r, N_l >= 0; free: M_l > 0,
// B_l, K_l >= 0; all finite) or a sample time < 0 (or not finite).
RfseaResponse rfsea_response(RfseaTest test, const RfseaParams& p, const RfseaConstants& c,
                             const std::vector<double>& f_hz, const SamplingModel& sampling = {});

// Continuous state space, input i (A), outputs F (N), theta_m (rad), q (rad).
// Free: states x_l, x_r (m), v_l, v_r (m/s) in the mass-matrix form
//   [J'+M_l  J'   ] [a_l]   [B'+B_l  B'    ] [v_l]   [K_l 0  ] [x_l]   [G]
//   [J'      J'+M_r] [a_r] + [B'      B'+B_r] [v_r] + [0   K_r] [x_r] = [G] i.
// Locked: states x_r, v_r:  (J'+M_r) a_r + (B'+B_r) v_r + K_r x_r = G i.
// InputError for parameters out of range, as rfsea_response.
blocks::StateSpace rfsea_state_space(RfseaTest test, const RfseaParams& p, const RfseaConstants& c);

// Largest chirp amplitude (A) that keeps the steady-state joint swing |q| below
// q_max_rad over [f0, f1] in the free test: q_max / max |q/I|. (The free load is a
// mass-damper on a weak spring: |q/I| grows as 1/f below the damper's corner, so a
// sweep from 0.01 Hz needs a tiny current; see the tests for the numbers.) The maximum is
// taken over 400 log-spaced frequencies. InputError unless 0 < f0 <= f1, q_max > 0 and
// N_l > 0.
double rfsea_free_test_max_amplitude(const RfseaParams& p, const RfseaConstants& c, double f0_hz, double f1_hz,
                                     double q_max_rad);

// ---------------------------------------------------------------------------------
// Identification

// One measured channel: H per ampere at the test's frequencies, with weights
// ~1/std(log H) (FrequencyResponseEstimate::weight). Empty H: channel not used; empty
// weight: all 1.
struct RfseaChannel {
  std::vector<Complex> H;       // per frequency: F in N/A, theta_m and q in rad/A (finite, non-zero)
  std::vector<double> weight;   // per frequency, >= 0
};
// One test's measured responses (rfsea_test_data makes them from a record).
struct RfseaTestData {
  std::vector<double> f_hz;  // empty: test not done
  RfseaChannel F,            // the elastomer force
      theta_m,               // the motor angle
      q;                     // the joint angle (needs RfseaConstants::N_l > 0)
};
// Everything identify_rfsea fits to: both tests (at least one) and what is known.
struct RfseaSysidData {
  RfseaConstants constants;  // k_tau, N_m, N_l: not fitted
  SamplingModel sampling;  // set ts_s to the record's sample time
  // The test with the output locked (needed by rfsea_initial_guess).
  RfseaTestData locked, free;  // the test with the output free (empty: the load is not fitted)
};

// Time records of one test (same length, sampled at fs): current (A), force (N), motor
// angle (rad), joint angle (rad; empty when not measured).
struct RfseaRecord {
  std::vector<double> i,  // the motor current, A (the input)
      F,                  // the elastomer force, N
      theta_m,            // the motor angle, rad
      q;                  // the joint angle, rad (empty: not measured)
};
// Estimates every channel of a record at f_hz (weights from the estimate). InputError
// as estimate_frequency_responses (records of different lengths included).
RfseaTestData rfsea_test_data(const RfseaRecord& record, double fs_hz, const std::vector<double>& f_hz,
                              const FrfOptions& options = {});

// How identify_rfsea fits.
struct RfseaFitOptions {
  // Start of the fit; default rfsea_initial_guess(data).
  std::optional<RfseaParams> initial;
  // Parameters not fitted (by RfseaParam index), held at fixed_values (whose K_l
  // defaults to 0, the usual choice when the load has no spring). The load parameters
  // are fixed automatically when there is no free test.
  std::array<bool, kRfseaNumParams> fixed{};
  RfseaParams fixed_values{};  // the values of the parameters marked in `fixed`
  // Residual evaluations allowed over both stages (a Jacobian takes two per free
  // parameter: central differences).
  int max_evaluations = 4000;
};

// What identify_rfsea found.
struct RfseaFit {
  RfseaParams params;   // the identified parameters (the fixed ones at fixed_values)
  RfseaParams initial;  // where it started (RfseaFitOptions::initial or the guess, fixed ones set)
  // 1-sigma relative standard deviations from the Jacobian at the solution, scaled by
  // the residual (0 for fixed parameters): how well the data determine each one
  // (conservative for M_r by about 1.5x in the tests).
  std::array<double, kRfseaNumParams> relative_std{};
  // Weighted residual r_k = w_k log(H_meas / H_model) (real: log magnitude, imaginary:
  // phase in rad), stacked over tests, channels and frequencies.
  double rms_residual = 0;    // sqrt(sum |r_k|^2 / (2 n))
  double rms_log_error = 0;   // the same without weights: ~ relative error of the fit
  int iterations = 0;         // Levenberg-Marquardt iterations, both stages
  int evaluations = 0;        // residual evaluations, both stages (Jacobians included)
  bool converged = false;     // stopped on a tolerance (not on max_evaluations or a failure)
  std::string status;         // why it stopped, in words ("converged: ...", "stopped: ...", "failed: ...")
};

// Data-derived starting point, no prior knowledge of the parameters:
//   K_r = N_m |F/theta_m| in the locked test (exactly K_r/N_m at every frequency);
//   the motor equation Z_m Theta + Z_r X_r = G (per ampere, X_r = F/K_r, Theta =
//   theta_m/N_m; Theta = X_r when locked) of both tests is linear in J', B', M_r, B_r:
//   the locked rows give the sums J'+M_r, B'+B_r (its resonance), the free rows split
//   them; the load equation Z_l (Theta - X_r) = Z_r X_r is linear in M_l, B_l, K_l.
//   Equation-error least squares, after removing the hold's first-order effect
//   (half-sample lag and sinc). Without a free test the sums are split 99:1.
// Parameters marked in `fixed` take fixed_values and are moved to the right-hand side.
// InputError when the locked test lacks F or theta_m.
RfseaParams rfsea_initial_guess(const RfseaSysidData& data, const std::array<bool, kRfseaNumParams>& fixed = {},
                                const RfseaParams& fixed_values = {});

// Levenberg-Marquardt (Eigen's unsupported module) on log-parameters minimising the
// weighted log-complex error over both tests and every channel present, in two
// stages: M_r (0.2 % of the moving mass, the weakest parameter) held at its start,
// then everything free. InputError for inconsistent data, and when the locked test
// is alone and neither J_m nor M_r (or neither B_m nor B_r) is fixed: they are then
// not identifiable. Inconsistent: ts_s < 0, a frequency outside (0, 1/(2 ts_s)), a
// channel whose H or weight does not match f_hz or holds a zero or non-finite value, no
// test, a q channel with N_l = 0, every parameter fixed, fewer residuals than free
// parameters, or a free parameter's start not > 0.
RfseaFit identify_rfsea(const RfseaSysidData& data, const RfseaFitOptions& options = {});

}  // namespace dmbd::experiments
