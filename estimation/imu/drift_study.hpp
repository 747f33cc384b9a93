// The drift study of section 57.1, measured rather than quoted: a robot standing still with a
// constant attitude R0, IMU readings synthesised by model/imu_model.hpp (true biases, optional
// white noise and bias random walk), integrated by dead reckoning that does not know the biases
// (b_hat = 0). The truth stays at v = 0, p = 0, R = R0, so the integrated state is the error.
// For a constant accelerometer bias b_a alone: |dv| = b_a t, |dp| = b_a t^2 / 2 (0.005 m at 1 s,
// 0.5 m at 10 s, 18 m at 60 s for 0.01 m/s^2); a gyro bias b_g alone tilts the attitude by
// |b_g| t (34 deg after 60 s for 0.01 rad/s) and, through the tilted gravity, drags position
// away as |g| |b_g| t^3 / 6 for a horizontal b_g.
#pragma once

#include <vector>

#include "lie/so3.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"

namespace legkit::imu {

struct StationaryDriftStudy {
  model::ImuBias bias;                                   // true biases, unknown to the integrator
  model::ImuNoise noise = model::ImuNoise::noiseless();  // sensor noise (default: bias only)
  lie::SO3d R0;                                          // the robot's constant attitude
  double dt = 1e-3;                                      // IMU period [s] (1 kHz)
  double duration = 60.0;                                // [s]
  double report_every = 0.1;                             // [s], a multiple of dt
  unsigned seed = 1;                                     // generator seed for the noise
};

// Error of the dead-reckoned state at time t (the truth is at rest).
struct DriftSample {
  double t = 0.0;                   // [s]
  double position_error = 0.0;      // |p_hat - p| [m]
  double velocity_error = 0.0;      // |v_hat - v| [m/s]
  double attitude_error_deg = 0.0;  // |Log(R^T R_hat)| [deg]
};

// Runs the study; one sample every report_every seconds, the first at t = 0.
// Throws std::invalid_argument for a non-positive dt, duration or report_every.
std::vector<DriftSample> runStationaryDrift(const StationaryDriftStudy& study);

// The sample nearest to time t (samples as returned by runStationaryDrift).
DriftSample driftAt(const std::vector<DriftSample>& samples, double t);

}  // namespace legkit::imu
