// IMU noise parameters as a datasheet gives them: continuous-time densities.
#pragma once

#include <cmath>

namespace legkit::model {

struct ImuNoise {
  double gyro_noise_density = 0.004;    // sigma_g  [rad/s/sqrt(Hz)]
  double accel_noise_density = 0.04;    // sigma_a  [m/s^2/sqrt(Hz)]
  double gyro_bias_random_walk = 5e-5;  // sigma_bg [rad/s^2/sqrt(Hz)]
  double accel_bias_random_walk = 5e-4; // sigma_ba [m/s^3/sqrt(Hz)]

  // The chapter's Unitree Go2 table (section 57.2).
  static ImuNoise go2() { return {}; }
  // A perfect sensor: no white noise, constant biases (for bias-only studies).
  static ImuNoise noiseless() { return {0.0, 0.0, 0.0, 0.0}; }

  // Discretisation at sample period dt: white noise of one sample has standard deviation
  // density / sqrt(dt); the bias random walk moves by density * sqrt(dt) per sample.
  double gyroSampleSigma(double dt) const { return gyro_noise_density / std::sqrt(dt); }
  double accelSampleSigma(double dt) const { return accel_noise_density / std::sqrt(dt); }
  double gyroBiasStepSigma(double dt) const { return gyro_bias_random_walk * std::sqrt(dt); }
  double accelBiasStepSigma(double dt) const { return accel_bias_random_walk * std::sqrt(dt); }
};

}  // namespace legkit::model
