#pragma once
// Sensor models, each seeded for repeatability (std::mt19937_64).

#include <Eigen/Core>

#include <cstdint>
#include <random>

namespace dmbd::model {

// Quadrature encoder: counts = floor(position * counts_per_unit) (4x decoding already
// in counts_per_unit), position read back as counts / counts_per_unit (so the read-back
// is never above the position and less than one count below it).
struct EncoderParams {
  double counts_per_unit = 4 * 2048 / (2 * 3.14159265358979323846);  // per rad (motor) or per m
};
class Encoder {
 public:
  explicit Encoder(const EncoderParams& p = {}) : p_(p) {}
  int64_t counts(double position) const;
  double read(double position) const;  // quantised position
  double resolution() const { return 1.0 / p_.counts_per_unit; }

 private:
  EncoderParams p_;
};

// Linear potentiometer on the joint: white noise, ADC quantisation over a range, then a
// first-order low-pass at cutoff_hz sampled at the read rate.
//   u = position + noise_std * n,  code = clamp(round((u - lo) / lsb), 0, 2^bits - 1),
//   v = lo + code * lsb,  lsb = (hi - lo) / (2^bits - 1),
//   y += a (v - y),  a = 1 - exp(-2 pi cutoff_hz dt)   (y = v when cutoff_hz = 0).
// The first read after construction starts the filter at v; reset(p) starts it at p.
// With noise_std large against lsb (quantisation noise ~ uniform, variance lsb^2/12),
// the filtered noise has variance a / (2 - a) (noise_std^2 + lsb^2 / 12).
struct PotentiometerParams {
  double lo = -3.2, hi = 3.2;   // range mapped onto the ADC (rad)
  int adc_bits = 12;
  double noise_std = 2e-3;      // rad, before the ADC
  double cutoff_hz = 100;       // 0: no filter
};
class Potentiometer {
 public:
  // Throws ModelError for hi <= lo, adc_bits outside 1..30, negative noise or cutoff.
  Potentiometer(const PotentiometerParams& p, uint64_t seed);
  void reset(double position);
  double read(double position, double dt_s);  // one sample, dt since the last one
  double lsb() const { return (p_.hi - p_.lo) / (static_cast<double>(int64_t{1} << p_.adc_bits) - 1.0); }

 private:
  PotentiometerParams p_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> n_{0.0, 1.0};
  double y_ = 0;
  bool first_ = true;
  double filter_dt_ = -1, filter_a_ = 0;  // the filter's gain for the last dt (the same every tick)
};

// Torso IMU: gyro and accelerometer with constant bias, white noise and a bias random
// walk; inputs are the true body-frame angular velocity and specific force.
// The initial biases are drawn at construction (bias_std per axis); each read first
// walks them (bias += bias_walk sqrt(dt) n), then returns truth + bias + noise_std n.
struct ImuParams {
  double gyro_noise_std = 2e-3;           // rad/s per sample
  double gyro_bias_std = 5e-3;            // rad/s, initial bias spread
  double gyro_bias_walk = 1e-5;           // rad/s per sqrt(s)
  double accel_noise_std = 2e-2;          // m/s^2 per sample
  double accel_bias_std = 5e-2;           // m/s^2
  double accel_bias_walk = 1e-4;          // m/s^2 per sqrt(s)
};
struct ImuReading {
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
};
class Imu {
 public:
  Imu(const ImuParams& p, uint64_t seed);
  ImuReading read(const Eigen::Vector3d& omega_B, const Eigen::Vector3d& specific_force_B, double dt_s);
  const Eigen::Vector3d& gyro_bias() const { return bg_; }
  const Eigen::Vector3d& accel_bias() const { return ba_; }

 private:
  ImuParams p_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> n_{0.0, 1.0};
  Eigen::Vector3d bg_, ba_;
};

}  // namespace dmbd::model
