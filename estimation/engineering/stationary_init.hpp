// Stationary initialisation (section 57.9): while the robot stands still, roll and pitch from the
// gravity direction, the gyro bias from the mean rate, and the filters' initial state and
// covariance from both.
#pragma once

namespace legkit::engineering {

struct StationaryInitParams {
  bool enabled = true;
  double duration = 2.0;       // [s] of standing still averaged (the chapter: 2-3 s)
  double gyro_std_max = 0.02;  // [rad/s] per axis: above it the robot is moving
  double accel_std_max = 0.3;  // [m/s^2] per axis
  double max_wait = 10.0;      // [s] without a still window: give up, start as the log does
};

}  // namespace legkit::engineering
