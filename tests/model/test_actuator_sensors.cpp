// Sensor models: quadrature encoders, the joint potentiometer (noise, ADC, low-pass) and
// the torso IMU. Statistical checks state their prediction and their tolerance in
// standard errors; every random stream is seeded, so each check is deterministic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "robot_files.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/sensors.hpp"

namespace dm = dmbd::model;

namespace {
constexpr double kPi = 3.14159265358979323846;

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}
double stddev(const std::vector<double>& v) {
  const double m = mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}
}  // namespace

// ---- Encoder ---------------------------------------------------------------------------

TEST(Encoder, ExactCountsForKnownPositionsIncludingNegative) {
  const dm::Encoder e({1000.0});  // 1 mrad per count
  // Mid-count positions are far (half a count) from any rounding question.
  for (int64_t k : {int64_t{0}, int64_t{1}, int64_t{7}, int64_t{123456}, int64_t{-1}, int64_t{-2}, int64_t{-98765}}) {
    const double pos = (static_cast<double>(k) + 0.5) / 1000.0;
    EXPECT_EQ(e.counts(pos), k) << pos;
    EXPECT_DOUBLE_EQ(e.read(pos), static_cast<double>(k) / 1000.0);
  }
  // floor, not truncation: just below zero is count -1
  EXPECT_EQ(e.counts(-0.25e-3), -1);
  EXPECT_EQ(e.counts(-1.5e-3), -2);
  EXPECT_EQ(e.counts(0.0), 0);
  EXPECT_DOUBLE_EQ(e.resolution(), 1e-3);
}

// Read-back error: 0 <= position - read < one count (plus rounding of the product, a few
// ulp of the position), over random positions of both signs, for DRACO's encoders.
TEST(Encoder, QuantisationErrorWithinOneCount) {
  const dm::ActuatorParams knee = dmbd::test::draco_actuators()[3];
  ASSERT_EQ(knee.joint, "l_knee");
  std::mt19937_64 rng(7);
  for (const dm::EncoderParams& p : {knee.motor_encoder, knee.spring_encoder}) {
    const dm::Encoder e(p);
    std::uniform_real_distribution<double> u(-2000.0 / p.counts_per_unit * 1000, 2000.0 / p.counts_per_unit * 1000);
    double worst = 0;
    for (int k = 0; k < 100000; ++k) {
      const double pos = u(rng);
      const double err = pos - e.read(pos);
      EXPECT_GE(err, -8 * std::numeric_limits<double>::epsilon() * std::abs(pos)) << pos;
      EXPECT_LT(err, e.resolution()) << pos;
      worst = std::max(worst, err);
    }
    EXPECT_GT(worst, 0.99 * e.resolution());  // and the whole count is used
  }
  // What the resolutions mean on the knee: motor encoder 2048 lines x 4 per revolution ->
  // 1.16e-7 m of screw travel per count (1/(counts/rad * N_m)); elastomer encoder 1 um per
  // count -> 9.5 N of sensed force per count (K_r = 9.5e6 N/m).
  EXPECT_NEAR(1.0 / (knee.motor_encoder.counts_per_unit * knee.N_m_rad_per_m), 1.157e-7, 1e-10);
  EXPECT_NEAR(knee.K_s_N_per_m / knee.spring_encoder.counts_per_unit, 9.5, 1e-12);
}

// ---- Potentiometer ---------------------------------------------------------------------

namespace {
dm::PotentiometerParams knee_pot() { return dmbd::test::draco_actuators()[3].potentiometer; }
}  // namespace

TEST(Potentiometer, SameSeedSameSequenceDifferentSeedsDiffer) {
  dm::Potentiometer a(knee_pot(), 42), b(knee_pot(), 42), c(knee_pot(), 43);
  int differ = 0;
  for (int k = 0; k < 2000; ++k) {
    const double q = 1.0 + 0.3 * std::sin(0.01 * k);
    const double ya = a.read(q, 1e-3), yb = b.read(q, 1e-3), yc = c.read(q, 1e-3);
    EXPECT_EQ(ya, yb) << k;  // bit for bit
    if (ya != yc) ++differ;
  }
  EXPECT_GT(differ, 1900);  // the noise (2 mrad, 3.7 LSB) makes nearly every sample differ
}

// Without noise and filter the reading is the ADC code: lo + an integer number of LSBs,
// within half an LSB of the position; a slow ramp shows every step of one LSB.
TEST(Potentiometer, AdcResolutionIsVisible) {
  dm::PotentiometerParams p = knee_pot();
  p.noise_std = 0;
  p.cutoff_hz = 0;
  dm::Potentiometer pot(p, 1);
  const double lsb = pot.lsb();
  EXPECT_NEAR(lsb, (2.19 - -0.05) / 4095, 1e-15);
  double prev = pot.read(0.5, 1e-3);
  int steps = 0;
  for (int k = 1; k <= 10000; ++k) {
    const double q = 0.5 + k * 1e-6;  // a 0.01 rad ramp, 18.3 LSB
    const double y = pot.read(q, 1e-3);
    const double codes = (y - p.lo) / lsb;
    EXPECT_NEAR(codes, std::round(codes), 1e-9) << q;
    EXPECT_LE(std::abs(y - q), lsb / 2 + 1e-12) << q;
    if (y != prev) {
      EXPECT_NEAR(y - prev, lsb, 1e-12) << q;
      ++steps;
    }
    prev = y;
  }
  EXPECT_GE(steps, 17);
  EXPECT_LE(steps, 19);
}

// The filter alone: from reset(0), one noiseless sample of v gives y = a v with
// a = 1 - exp(-2 pi fc dt), and successive samples approach v geometrically.
TEST(Potentiometer, FirstOrderLowPass) {
  dm::PotentiometerParams p = knee_pot();
  p.noise_std = 0;
  dm::Potentiometer pot(p, 1);
  pot.reset(0.0);
  const double dt = 1e-3, a = 1 - std::exp(-2 * kPi * p.cutoff_hz * dt);
  const double v = p.lo + std::round((1.0 - p.lo) / pot.lsb()) * pot.lsb();  // ADC value of 1.0
  double expect = 0;
  for (int k = 0; k < 20; ++k) {
    expect += a * (v - expect);
    EXPECT_NEAR(pot.read(1.0, dt), expect, 1e-14) << k;
  }
}

// Noise after the filter. Prediction: white input noise sigma_n plus uniform
// quantisation noise lsb^2/12 (accurate to exp(-2 pi^2 sigma_n^2/lsb^2) ~ 1e-100 here),
// through y_k = (1-a) y_{k-1} + a v_k: var y = a/(2-a) (sigma_n^2 + lsb^2/12).
// Knee potentiometer (2 mrad, 12 bit over 2.24 rad), 1 kHz, 100 Hz: 1.100 mrad.
// N = 200000 samples of an AR(1) with rho = 1-a: the standard error of the sample std is
// sigma sqrt((1+rho^2)/(2N(1-rho^2))) = 0.21%; bound 6 standard errors. The mean is within
// 6 standard errors sqrt(var y (1+rho)/(N(1-rho))) of the truth.
TEST(Potentiometer, FilteredNoiseMatchesPrediction) {
  const dm::PotentiometerParams p = knee_pot();
  dm::Potentiometer pot(p, 2024);
  const double dt = 1e-3, truth = 1.2345;
  const double a = 1 - std::exp(-2 * kPi * p.cutoff_hz * dt), rho = 1 - a;
  const double lsb = pot.lsb();
  const double predicted = std::sqrt(a / (2 - a) * (p.noise_std * p.noise_std + lsb * lsb / 12));
  for (int k = 0; k < 1000; ++k) pot.read(truth, dt);  // settle
  const int n = 200000;
  std::vector<double> y(n);
  for (int k = 0; k < n; ++k) y[k] = pot.read(truth, dt);
  const double s = stddev(y), m = mean(y);
  const double se_std = predicted * std::sqrt((1 + rho * rho) / (2.0 * n * (1 - rho * rho)));
  const double se_mean = predicted * std::sqrt((1 + rho) / (n * (1 - rho)));
  std::printf(
      "[ measured ] potentiometer noise after the filter: %.4e rad (predicted %.4e, unfiltered %.4e), mean "
      "error %.2e rad\n",
      s, predicted, std::sqrt(p.noise_std * p.noise_std + lsb * lsb / 12), m - truth);
  EXPECT_NEAR(s, predicted, 6 * se_std);
  EXPECT_NEAR(m, truth, 6 * se_mean);
}

TEST(Potentiometer, ClampsAtTheRangeEnds) {
  const dm::PotentiometerParams p = knee_pot();
  dm::Potentiometer hi(p, 3), lo(p, 4);
  double y_hi = 0, y_lo = 0;
  for (int k = 0; k < 500; ++k) {
    y_hi = hi.read(p.hi + 0.5, 1e-3);  // 250 noise sigmas beyond the end
    y_lo = lo.read(p.lo - 0.5, 1e-3);
  }
  EXPECT_NEAR(y_hi, p.hi, 1e-12);  // top code = lo + (2^bits - 1) lsb = hi
  EXPECT_NEAR(y_lo, p.lo, 1e-12);
  EXPECT_THROW(dm::Potentiometer({1.0, 1.0, 12, 0, 0}, 1), dm::ModelError);
  EXPECT_THROW(dm::Potentiometer({0.0, 1.0, 0, 0, 0}, 1), dm::ModelError);
}

// ---- IMU ----------------------------------------------------------------------------------

TEST(Imu, ReproducibleWithSeed) {
  dm::Imu a({}, 9), b({}, 9), c({}, 10);
  EXPECT_EQ(a.gyro_bias(), b.gyro_bias());
  EXPECT_NE(a.gyro_bias(), c.gyro_bias());
  const Eigen::Vector3d w(0.1, -0.2, 0.3), f(0, 0, 9.81);
  for (int k = 0; k < 1000; ++k) {
    const dm::ImuReading ra = a.read(w, f, 1e-3), rb = b.read(w, f, 1e-3), rc = c.read(w, f, 1e-3);
    EXPECT_EQ(ra.gyro_rad_s, rb.gyro_rad_s);
    EXPECT_EQ(ra.accel_m_s2, rb.accel_m_s2);
    EXPECT_NE(ra.gyro_rad_s, rc.gyro_rad_s);
  }
}

// Initial biases across seeds have the configured spread: 2000 IMUs x 3 axes; the sample
// std of 6000 normals has a standard error of 0.9%: bound 5%.
TEST(Imu, InitialBiasSpread) {
  const dm::ImuParams p;
  std::vector<double> g, acc;
  for (uint64_t seed = 1; seed <= 2000; ++seed) {
    const dm::Imu imu(p, seed);
    for (int k = 0; k < 3; ++k) {
      g.push_back(imu.gyro_bias()[k]);
      acc.push_back(imu.accel_bias()[k]);
    }
  }
  EXPECT_NEAR(stddev(g), p.gyro_bias_std, 0.05 * p.gyro_bias_std);
  EXPECT_NEAR(stddev(acc), p.accel_bias_std, 0.05 * p.accel_bias_std);
}

// 60 s at 1 kHz, still robot (omega = 0, specific force = +g up): the bias only wanders by
// its random walk (std walk sqrt(T) = 7.7e-5 rad/s, 1.5% of the initial bias spread: bound 5
// sigma); the mean reading equals truth + initial bias within 5 sigma of
// sqrt(noise^2/N + walk^2 T/3) (white noise averaged, plus the mean of the walk); the
// residual reading - truth - current bias has the configured white-noise std (N = 60000:
// standard error 0.29%, bound 2%).
TEST(Imu, MeanIsTruthPlusBiasAndBiasIsNearlyConstant) {
  const dm::ImuParams p;
  dm::Imu imu(p, 77);
  const Eigen::Vector3d w(0.0, 0.0, 0.0), f(0.0, 0.0, 9.81);
  const Eigen::Vector3d bg0 = imu.gyro_bias(), ba0 = imu.accel_bias();
  const double dt = 1e-3, T = 60.0;
  const int n = static_cast<int>(T / dt);
  Eigen::Vector3d sum_g = Eigen::Vector3d::Zero(), sum_a = Eigen::Vector3d::Zero();
  std::vector<double> resid_g, resid_a;
  for (int k = 0; k < n; ++k) {
    const dm::ImuReading r = imu.read(w, f, dt);
    sum_g += r.gyro_rad_s;
    sum_a += r.accel_m_s2;
    resid_g.push_back((r.gyro_rad_s - w - imu.gyro_bias())[k % 3]);
    resid_a.push_back((r.accel_m_s2 - f - imu.accel_bias())[k % 3]);
  }
  const Eigen::Vector3d mean_g = sum_g / n, mean_a = sum_a / n;
  const double sig_g = std::sqrt(p.gyro_noise_std * p.gyro_noise_std / n + p.gyro_bias_walk * p.gyro_bias_walk * T / 3);
  const double sig_a =
      std::sqrt(p.accel_noise_std * p.accel_noise_std / n + p.accel_bias_walk * p.accel_bias_walk * T / 3);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(imu.gyro_bias()[k], bg0[k], 5 * p.gyro_bias_walk * std::sqrt(T)) << k;
    EXPECT_NEAR(imu.accel_bias()[k], ba0[k], 5 * p.accel_bias_walk * std::sqrt(T)) << k;
    EXPECT_NEAR(mean_g[k], w[k] + bg0[k], 5 * sig_g) << k;
    EXPECT_NEAR(mean_a[k], f[k] + ba0[k], 5 * sig_a) << k;
  }
  EXPECT_NEAR(stddev(resid_g), p.gyro_noise_std, 0.02 * p.gyro_noise_std);
  EXPECT_NEAR(stddev(resid_a), p.accel_noise_std, 0.02 * p.accel_noise_std);
}
