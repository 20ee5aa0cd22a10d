// Encoder, potentiometer and IMU models (see sensors.hpp for the equations).
#include "dmbd/model/sensors.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "dmbd/model/error.hpp"

namespace dmbd::model {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

// ---- Encoder ------------------------------------------------------------------------

int64_t Encoder::counts(double position) const {
  return static_cast<int64_t>(std::floor(position * p_.counts_per_unit));
}

double Encoder::read(double position) const { return static_cast<double>(counts(position)) / p_.counts_per_unit; }

// ---- Potentiometer --------------------------------------------------------------------

Potentiometer::Potentiometer(const PotentiometerParams& p, uint64_t seed) : p_(p), rng_(seed) {
  if (!(p.hi > p.lo) || !std::isfinite(p.lo) || !std::isfinite(p.hi))
    throw ModelError("potentiometer: range must have hi > lo, got [" + std::to_string(p.lo) + ", " +
                     std::to_string(p.hi) + "]");
  if (p.adc_bits < 1 || p.adc_bits > 30)
    throw ModelError("potentiometer: adc_bits must be 1..30, got " + std::to_string(p.adc_bits));
  if (!(p.noise_std >= 0) || !(p.cutoff_hz >= 0))
    throw ModelError("potentiometer: noise_std and cutoff_hz must be >= 0");
}

void Potentiometer::reset(double position) {
  y_ = position;
  first_ = false;
}

double Potentiometer::read(double position, double dt_s) {
  const double u = position + p_.noise_std * n_(rng_);
  const double top = static_cast<double>(int64_t{1} << p_.adc_bits) - 1.0;
  const double step = lsb();
  const double code = std::clamp(std::round((u - p_.lo) / step), 0.0, top);
  const double v = p_.lo + code * step;
  if (first_ || p_.cutoff_hz <= 0) {
    y_ = v;
    first_ = false;
    return y_;
  }
  if (dt_s != filter_dt_) {
    filter_dt_ = dt_s;
    filter_a_ = -std::expm1(-2.0 * kPi * p_.cutoff_hz * std::max(dt_s, 0.0));
  }
  y_ += filter_a_ * (v - y_);
  return y_;
}

// ---- IMU -------------------------------------------------------------------------------

Imu::Imu(const ImuParams& p, uint64_t seed) : p_(p), rng_(seed) {
  for (int k = 0; k < 3; ++k) bg_[k] = p_.gyro_bias_std * n_(rng_);
  for (int k = 0; k < 3; ++k) ba_[k] = p_.accel_bias_std * n_(rng_);
}

ImuReading Imu::read(const Eigen::Vector3d& omega_B, const Eigen::Vector3d& specific_force_B, double dt_s) {
  const double sq = std::sqrt(std::max(dt_s, 0.0));
  ImuReading r;
  for (int k = 0; k < 3; ++k) {
    bg_[k] += p_.gyro_bias_walk * sq * n_(rng_);
    r.gyro_rad_s[k] = omega_B[k] + bg_[k] + p_.gyro_noise_std * n_(rng_);
  }
  for (int k = 0; k < 3; ++k) {
    ba_[k] += p_.accel_bias_walk * sq * n_(rng_);
    r.accel_m_s2[k] = specific_force_B[k] + ba_[k] + p_.accel_noise_std * n_(rng_);
  }
  return r;
}

}  // namespace dmbd::model
