// IMU noise parameters as a datasheet gives them: continuous-time densities.
#pragma once

#include <cmath>

namespace legkit::model {

struct ImuNoise {
  double gyro_noise_density = 0.004;     // sigma_g  [rad/s/sqrt(Hz)]
  double accel_noise_density = 0.04;     // sigma_a  [m/s^2/sqrt(Hz)]
  double gyro_bias_random_walk = 5e-5;   // sigma_bg [rad/s^2/sqrt(Hz)]
  double accel_bias_random_walk = 5e-4;  // sigma_ba [m/s^3/sqrt(Hz)]

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

// The largest noise any IMU at rest shows, 100x or more beyond a consumer MEMS sensor's (white
// noise 1e-3 to 1e-2 rad/s/sqrt(Hz) and 0.01 to 0.1 m/s^2/sqrt(Hz); bias random walk 1e-5 to
// 1e-3 rad/s^2/sqrt(Hz) and 1e-4 to 1e-2 m/s^3/sqrt(Hz)). The settings file refuses more
// (imu.*), and `legkit allan` calls a record that reads more one that moved: a 10 s simulated
// trot reads a gyro bias random walk of 0.32 to 1.04, a walking robot's real log 0.84.
struct ImuNoiseLimits {
  static constexpr double gyro_noise_density = 1.0;      // [rad/s/sqrt(Hz)]
  static constexpr double accel_noise_density = 10.0;    // [m/s^2/sqrt(Hz)]
  static constexpr double gyro_bias_random_walk = 0.1;   // [rad/s^2/sqrt(Hz)]
  static constexpr double accel_bias_random_walk = 1.0;  // [m/s^3/sqrt(Hz)]
};

}  // namespace legkit::model
