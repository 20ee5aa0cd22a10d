// Identification of the knee RFSEA from synthetic chirp experiments (paper Fig. 5a):
// locked and free tests simulated exactly (ZOH) at the 2 kHz controller rate with the
// Table I values, with and without sensor noise, then estimated and fitted by
// sim/sysid. The simulated plant is rfsea_state_space, which test_sysid_model.cpp
// checks against the shipped diagram, a transfer-function interconnection and the
// doc's own realisation.
//
// The experiments (chosen for a fast test that still resolves every parameter):
//   locked: 1 -> 200 Hz in 20 s, 4 A (peak force ~3.9 kN at the 18.5 Hz resonance,
//           under the 8 kN limit); estimated at 60 frequencies 1 .. 150 Hz.
//   free:   0.5 -> 200 Hz in 40 s, 2.5 A, 2 s fade-in (the joint swings 0.15 rad at
//           most; rfsea_free_test_max_amplitude gives 3.05 A for 0.2 rad from 0.5 Hz);
//           80 frequencies 0.5 .. 150 Hz.
// Both with a 0.2 s quiet lead-in (baseline) and a quiet tail (1 s / 2 s) to settle.
// Records of 43 k and 85 k samples: simulation, estimation and fit take ~50 ms.
// Estimation above 150 Hz adds little: the responses fall as 1/f^2 and the hold's
// aliasing grows.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dmbd/blocks/time_response.hpp"
#include "dmbd/model/sensors.hpp"
#include "dmbd/experiments/sysid.hpp"

namespace {

using namespace dmbd;  // NOLINT
using experiments::RfseaTest;

constexpr double kFs = 2000;  // controller rate, Hz

struct Noise {
  double force_N = 0;           // white, rms
  bool motor_encoder = false;   // quantised to 2 pi / (4 * 2048) rad (model::Encoder)
  double joint_rad = 0;         // white, rms
};
const Noise kRealistic{2.0, true, 1e-3};

struct Experiment {
  experiments::ExponentialChirp chirp;
  double lead_in_s, tail_s;
  double f_lo_hz, f_hi_hz;
  int n_freqs;
};
const Experiment kLocked{{1.0, 200, 20, 4.0, 1.0, 0.05}, 0.2, 1.0, 1.0, 150, 60};
const Experiment kFree{{0.5, 200, 40, 2.5, 2.0, 0.05}, 0.2, 2.0, 0.5, 150, 80};

// Table I knee values; a free load like the shank swinging (M_l = I N_l^2 with
// I ~ 0.4 kg m^2, N_l = 20 rad/m; gravity through the linkage K_l) or, at the other
// end of the range, the doc's stance value 2953 kg.
experiments::RfseaParams truth(double M_l = 150) {
  experiments::RfseaParams p;
  p.M_l = M_l;
  p.B_l = 2.0e4;
  p.K_l = 3000;
  return p;
}

experiments::RfseaRecord simulate(RfseaTest test, const experiments::RfseaParams& p, const Experiment& e, const Noise& noise,
                          uint64_t seed) {
  const experiments::RfseaConstants c;
  const auto u = e.chirp.sample(kFs, e.lead_in_s, e.tail_s);
  const blocks::Matrix um = Eigen::Map<const Eigen::VectorXd>(u.data(), static_cast<Eigen::Index>(u.size()));
  const auto y = blocks::lsim(experiments::rfsea_state_space(test, p, c), um, 1.0 / kFs).y;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  const model::Encoder encoder;  // 4 x 2048 counts per motor revolution
  experiments::RfseaRecord r;
  r.i = u;
  for (Eigen::Index k = 0; k < y.rows(); ++k) {
    r.F.push_back(y(k, 0) + noise.force_N * n01(rng));
    r.theta_m.push_back(noise.motor_encoder ? encoder.read(y(k, 1)) : y(k, 1));
    if (test == RfseaTest::Free) r.q.push_back(y(k, 2) + noise.joint_rad * n01(rng));
  }
  return r;
}

// Baseline from the lead-in. With noise, the end value from the last 0.5 s (the
// free load's slow mode, tau ~ 10 s, still drifts there: without noise the last
// sample is the better end value).
experiments::FrfOptions frf_options(const Noise& noise) {
  experiments::FrfOptions o;
  o.baseline_s = 0.2;
  if (noise.force_N > 0) o.tail_average_s = 0.5;
  return o;
}

experiments::RfseaTestData measure(RfseaTest test, const experiments::RfseaParams& p, const Experiment& e, const Noise& noise,
                           uint64_t seed) {
  return experiments::rfsea_test_data(simulate(test, p, e, noise, seed), kFs,
                              experiments::log_frequencies(e.f_lo_hz, e.f_hi_hz, e.n_freqs), frf_options(noise));
}

experiments::RfseaSysidData make_data(const experiments::RfseaParams& p, const Noise& noise, uint64_t seed) {
  experiments::RfseaSysidData d;
  d.sampling.ts_s = 1.0 / kFs;
  d.locked = measure(RfseaTest::Locked, p, kLocked, noise, seed);
  d.free = measure(RfseaTest::Free, p, kFree, noise, seed + 1);
  return d;
}

std::array<double, experiments::kRfseaNumParams> rel_errors(const experiments::RfseaParams& est, const experiments::RfseaParams& truth) {
  const auto t = experiments::to_array(truth), x = experiments::to_array(est);
  std::array<double, experiments::kRfseaNumParams> e{};
  for (std::size_t j = 0; j < t.size(); ++j) e[j] = x[j] / t[j] - 1;
  return e;
}

void print(const char* what, const experiments::RfseaFit& fit, const experiments::RfseaParams& truth) {
  const auto g = rel_errors(fit.initial, truth), x = rel_errors(fit.params, truth);
  std::printf("%s: %s, %d iterations, %d evaluations, rms residual %.3g, rms log error %.3g\n", what,
              fit.status.c_str(), fit.iterations, fit.evaluations, fit.rms_residual, fit.rms_log_error);
  for (int j = 0; j < experiments::kRfseaNumParams; ++j) {
    const auto u = static_cast<std::size_t>(j);
    std::printf("  %-4s guess %+9.4f %%   fit %+9.4f %%   (1-sigma %.4f %%)\n", experiments::rfsea_param_name(j), 100 * g[u],
                100 * x[u], 100 * fit.relative_std[u]);
  }
}

TEST(SysidIdentify, NoiseFreeChirpsRecoverEveryParameter) {
  // The spec asks for 2 %; measured: M_r 3.6e-5 and K_l 6.7e-5, the rest below
  // 1e-5 at M_l = 150 kg; M_r 2.6e-4 at 2953 kg. Asserted at 0.1 %, for both ends of
  // the load range. The start is the data-derived guess (no knowledge of the truth).
  for (double M_l : {150.0, 2953.0}) {
    SCOPED_TRACE(M_l);
    const experiments::RfseaParams p = truth(M_l);
    const experiments::RfseaFit fit = experiments::identify_rfsea(make_data(p, {}, 1));
    print(M_l < 1000 ? "noise-free, M_l 150 kg" : "noise-free, M_l 2953 kg", fit, p);
    EXPECT_TRUE(fit.converged) << fit.status;
    const auto e = rel_errors(fit.params, p);
    for (int j = 0; j < experiments::kRfseaNumParams; ++j)
      EXPECT_LT(std::abs(e[static_cast<std::size_t>(j)]), 1e-3) << experiments::rfsea_param_name(j);
    // The fit residual: the estimates are not exactly the model (local-fit bias
    // ~1e-5, the free load's slow mode still decaying at the record's end): a
    // relative rms error of ~2e-5.
    EXPECT_LT(fit.rms_log_error, 2e-4);
  }
}

TEST(SysidIdentify, NoisyChirpsRecoverEveryParameter) {
  // Force noise 2 N rms, motor encoder quantised to 2 pi/8192 rad, joint angle noise
  // 1e-3 rad. The spec asks for 10 %. M_r is the weak one: it is 0.2 % of the mass
  // the elastomer carries (J' = 704 kg). Over 20 seeds (M_l = 150 kg) the rms errors
  // were M_r 1.1 %, K_l 0.065 %, B_m 0.012 %, the rest below 0.006 %; worst M_r 2.5 %,
  // K_l 0.14 %. The fit's own 1-sigma for M_r (1.7 %) is conservative. Five seeds
  // here, each parameter within 10 % and within 4 of the fit's standard deviations.
  const experiments::RfseaParams p = truth();
  for (uint64_t seed = 11; seed <= 15; ++seed) {
    SCOPED_TRACE(seed);
    const experiments::RfseaFit fit = experiments::identify_rfsea(make_data(p, kRealistic, seed * 101));
    if (seed == 11) print("noisy, M_l 150 kg", fit, p);
    EXPECT_TRUE(fit.converged) << fit.status;
    const auto e = rel_errors(fit.params, p);
    for (int j = 0; j < experiments::kRfseaNumParams; ++j) {
      const auto u = static_cast<std::size_t>(j);
      EXPECT_LT(std::abs(e[u]), 0.10) << experiments::rfsea_param_name(j);
      EXPECT_LT(std::abs(e[u]), 4 * fit.relative_std[u] + 1e-4) << experiments::rfsea_param_name(j);
    }
    // Weights are 1/std(log H), so the weighted residual is ~1 when the model fits.
    EXPECT_LT(fit.rms_residual, 2.0);
  }
  // Without the joint angle: q adds nothing that F and theta_m do not carry with far
  // less noise (x_l = theta_m/N_m - F/K_r; the encoder reads x_l to ~1e-7 m, the
  // joint angle to 5e-5 m), so a potentiometer whose filter is not modelled can be
  // left out. Over 20 seeds the errors were the same as with q.
  {
    experiments::RfseaSysidData d = make_data(p, kRealistic, 1111);
    d.free.q = {};
    const experiments::RfseaFit fit = experiments::identify_rfsea(d);
    EXPECT_TRUE(fit.converged) << fit.status;
    const auto e = rel_errors(fit.params, p);
    for (int j = 0; j < experiments::kRfseaNumParams; ++j)
      EXPECT_LT(std::abs(e[static_cast<std::size_t>(j)]), 0.10) << "without q: " << experiments::rfsea_param_name(j);
  }
  // The stance load (2953 kg, where the joint barely moves): still within 10 % (20
  // seeds: rms M_r 0.75 %, K_l 0.13 %, the rest below 0.02 %).
  const experiments::RfseaParams ps = truth(2953);
  experiments::RfseaSysidData d = make_data(ps, kRealistic, 7);
  const experiments::RfseaFit fit = experiments::identify_rfsea(d);
  print("noisy, M_l 2953 kg", fit, ps);
  const auto e = rel_errors(fit.params, ps);
  for (int j = 0; j < experiments::kRfseaNumParams; ++j)
    EXPECT_LT(std::abs(e[static_cast<std::size_t>(j)]), 0.10) << experiments::rfsea_param_name(j);
}

TEST(SysidIdentify, ConvergesFromPoorStarts) {
  // Starting every parameter a factor 3 off (alternately high and low, and in a second
  // pattern) the fit lands on the same minimum as from the data-derived guess. Without
  // the first stage that holds M_r, starts 1.5x off sent M_r to 0.
  const experiments::RfseaParams p = truth();
  const experiments::RfseaSysidData d = make_data(p, kRealistic, 5);
  const experiments::RfseaFit ref = experiments::identify_rfsea(d);
  const auto rp = experiments::to_array(ref.params);
  for (int pattern = 0; pattern < 2; ++pattern) {
    for (double factor : {1.5, 3.0}) {
      SCOPED_TRACE(::testing::Message() << "pattern " << pattern << " factor " << factor);
      auto a = experiments::to_array(p);
      for (std::size_t j = 0; j < a.size(); ++j)
        a[j] *= pattern == 0 ? (j % 2 == 0 ? factor : 1 / factor)
                             : (j % 3 == 0 ? factor : (j % 3 == 1 ? 1 / factor : std::sqrt(factor)));
      experiments::RfseaFitOptions o;
      o.initial = experiments::from_array(a);
      const experiments::RfseaFit fit = experiments::identify_rfsea(d, o);
      EXPECT_TRUE(fit.converged) << fit.status;
      const auto x = experiments::to_array(fit.params);
      for (std::size_t j = 0; j < x.size(); ++j)
        EXPECT_NEAR(x[j] / rp[j], 1.0, 1e-4) << experiments::rfsea_param_name(static_cast<int>(j));
    }
  }
}

TEST(SysidIdentify, InitialGuessComesFromTheData) {
  // The guess uses no parameter value: K_r from F/theta_m, the sums from the locked
  // resonance, the split and the load by equation-error least squares. Noise-free it
  // is within 1 % for M_r (the hold's first-order correction matters for the small
  // M_r), 0.5 % for K_l (seen only below ~1 Hz) and 0.1 % for the rest (measured
  // 0.93 %, 0.10 %, 0.014 %); with noise the weak M_r can be 20 % off and the rest
  // within 2 %.
  const experiments::RfseaParams p = truth();
  const auto g0 = rel_errors(experiments::rfsea_initial_guess(make_data(p, {}, 1)), p);
  const auto g1 = rel_errors(experiments::rfsea_initial_guess(make_data(p, kRealistic, 9)), p);
  for (int j = 0; j < experiments::kRfseaNumParams; ++j) {
    const auto u = static_cast<std::size_t>(j);
    EXPECT_LT(std::abs(g0[u]), j == experiments::kM_r ? 0.01 : (j == experiments::kK_l ? 5e-3 : 1e-3)) << experiments::rfsea_param_name(j);
    EXPECT_LT(std::abs(g1[u]), j == experiments::kM_r ? 0.3 : 0.02) << experiments::rfsea_param_name(j);
  }
}

TEST(SysidIdentify, LockedTestAloneGivesOnlyTheSums) {
  // Identifiability: with X_l = 0, F/I = G K_r / ((J' + M_r) s^2 + (B' + B_r) s + K_r)
  // and theta_m = N_m F / K_r: K_r and the two sums, nothing more.
  const experiments::RfseaParams p = truth();
  // The paper's band, 0.01 .. 200 Hz, over 200 s (the first cycles take minutes: the
  // estimator widens its bands to 7 bins of 1/(record) there).
  const Experiment paper{{0.01, 200, 200, 4.0, 20.0, 0.05}, 0.2, 1.0, 0.02, 150, 80};
  experiments::RfseaSysidData d;
  d.sampling.ts_s = 1.0 / kFs;
  d.locked = measure(RfseaTest::Locked, p, paper, kRealistic, 3);
  EXPECT_THROW(experiments::identify_rfsea(d), InputError);
  experiments::RfseaFitOptions o;
  o.fixed[experiments::kB_r] = true;
  EXPECT_THROW(experiments::identify_rfsea(d, o), InputError);  // J_m or M_r still needed
  // Fix the elastomer's mass and damping at a guess 1.5x and 0.5x off: the sums
  // still come out.
  o.fixed[experiments::kM_r] = true;
  o.fixed_values.M_r = 1.5 * p.M_r;
  o.fixed_values.B_r = 0.5 * p.B_r;
  const experiments::RfseaFit fit = experiments::identify_rfsea(d, o);
  EXPECT_TRUE(fit.converged) << fit.status;
  const experiments::RfseaConstants c;
  const double n2 = c.N_m * c.N_m;
  const auto& x = fit.params;
  EXPECT_NEAR(x.K_r / p.K_r, 1.0, 1e-3);
  EXPECT_NEAR((x.J_m * n2 + x.M_r) / (p.J_m * n2 + p.M_r), 1.0, 1e-3);
  EXPECT_NEAR((x.B_m * n2 + x.B_r) / (p.B_m * n2 + p.B_r), 1.0, 2e-3);
  EXPECT_EQ(x.M_r, 1.5 * p.M_r);
  EXPECT_EQ(x.B_r, 0.5 * p.B_r);
  EXPECT_EQ(x.M_l, o.fixed_values.M_l);  // the load is not fitted without a free test
}

TEST(SysidIdentify, LoadSpringIsANuisanceToFitOrFix) {
  // With K_l = 0 in the plant, fixing it to 0 is exact. With gravity (K_l = 3000 N/m)
  // fixing it to 0 leaves a misfit the residual shows (rms ~20 against ~1), and M_r
  // absorbs it: fit K_l when in doubt.
  experiments::RfseaParams p = truth();
  p.K_l = 0;
  experiments::RfseaFitOptions o;
  o.fixed[experiments::kK_l] = true;
  const experiments::RfseaFit a = experiments::identify_rfsea(make_data(p, {}, 1), o);
  EXPECT_EQ(a.params.K_l, 0.0);
  const auto e = rel_errors(a.params, p);
  for (int j = 0; j < experiments::kK_l; ++j) EXPECT_LT(std::abs(e[static_cast<std::size_t>(j)]), 1e-3) << experiments::rfsea_param_name(j);

  const experiments::RfseaSysidData d = make_data(truth(), kRealistic, 2);
  const experiments::RfseaFit fitted = experiments::identify_rfsea(d);
  const experiments::RfseaFit fixed0 = experiments::identify_rfsea(d, o);
  std::printf("K_l fitted: rms residual %.3g; K_l fixed at 0: rms residual %.3g, M_r %+.1f %%\n", fitted.rms_residual,
              fixed0.rms_residual, 100 * (fixed0.params.M_r / 1.3 - 1));
  EXPECT_GT(fixed0.rms_residual, 5 * fitted.rms_residual);
}

TEST(SysidIdentify, FreeTestAmplitudeKeepsTheJointWithinRange) {
  // The free load is a mass-damper on a weak spring: below its damper corner |q/I|
  // grows as 1/f, so the lowest frequency sets the amplitude. For 0.2 rad:
  // from 0.01 Hz: 0.118 A;  0.1 Hz: 0.62 A;  0.3 Hz: 1.83 A;  0.5 Hz: 3.05 A;  1 Hz: 6.2 A
  // (M_l = 150 kg; about the same at 2953 kg, where the dampers dominate).
  const experiments::RfseaConstants c;
  const experiments::RfseaParams p = truth();
  EXPECT_NEAR(experiments::rfsea_free_test_max_amplitude(p, c, 0.01, 200, 0.2), 0.118, 0.002);
  EXPECT_NEAR(experiments::rfsea_free_test_max_amplitude(p, c, 0.5, 200, 0.2), 3.05, 0.01);
  // The chirp at that amplitude, simulated: the swing stays near 0.2 rad (the
  // steady-state bound; the 2 s fade-in keeps the start from adding a drift).
  Experiment e = kFree;
  e.chirp.amplitude = experiments::rfsea_free_test_max_amplitude(p, c, e.chirp.f0_hz, e.chirp.f1_hz, 0.2);
  const auto rec = simulate(RfseaTest::Free, p, e, {}, 1);
  double q_max = 0;
  for (double q : rec.q) q_max = std::max(q_max, std::abs(q));
  std::printf("free test %.2f .. %.0f Hz at %.2f A: max |q| %.3f rad\n", e.chirp.f0_hz, e.chirp.f1_hz,
              e.chirp.amplitude, q_max);
  EXPECT_LT(q_max, 0.2 * 1.05);
  EXPECT_GT(q_max, 0.2 * 0.8);
}

TEST(SysidIdentify, ModelResponseForTheBodePlot) {
  // rfsea_response of the identified parameters against the measured response: what
  // a Bode plot of the fit draws. Noise-free, they agree to 1e-4 except at the free
  // test's lowest frequencies (2.9e-4 at 0.54 Hz, where the load's slow mode, still
  // decaying when the record ends, leaks in): tolerance 1e-3.
  const experiments::RfseaParams p = truth();
  const experiments::RfseaSysidData d = make_data(p, {}, 1);
  const experiments::RfseaFit fit = experiments::identify_rfsea(d);
  const auto m = experiments::rfsea_response(RfseaTest::Free, fit.params, d.constants, d.free.f_hz, d.sampling);
  for (std::size_t k = 0; k < d.free.f_hz.size(); ++k) {
    EXPECT_LT(std::abs(m.F[k] / d.free.F.H[k] - 1.0), 1e-3) << d.free.f_hz[k];
    EXPECT_LT(std::abs(m.theta_m[k] / d.free.theta_m.H[k] - 1.0), 1e-3) << d.free.f_hz[k];
    EXPECT_LT(std::abs(m.q[k] / d.free.q.H[k] - 1.0), 1e-3) << d.free.f_hz[k];
  }
}

TEST(SysidIdentify, RejectsInconsistentData) {
  experiments::RfseaSysidData d = make_data(truth(), {}, 1);
  experiments::RfseaSysidData bad = d;
  bad.locked.F.H.pop_back();
  EXPECT_THROW(experiments::identify_rfsea(bad), InputError);
  bad = d;
  bad.free.f_hz.back() = 1500;  // above Nyquist
  EXPECT_THROW(experiments::identify_rfsea(bad), InputError);
  bad = d;
  bad.locked.theta_m = {};
  EXPECT_THROW(experiments::rfsea_initial_guess(bad), InputError);  // K_r needs F/theta_m
  bad = d;
  bad.constants.N_l = 0;
  EXPECT_THROW(experiments::identify_rfsea(bad), InputError);  // a q channel without N_l
  experiments::RfseaFitOptions o;
  o.fixed.fill(true);
  EXPECT_THROW(experiments::identify_rfsea(d, o), InputError);
  o.fixed.fill(false);
  experiments::RfseaParams start = truth();
  start.K_l = 0;  // a fitted parameter must start > 0 (log space)
  o.initial = start;
  EXPECT_THROW(experiments::identify_rfsea(d, o), InputError);
}

}  // namespace
