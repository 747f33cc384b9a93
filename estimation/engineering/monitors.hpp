// Sensor-health and covariance monitors with graceful degradation (section 57.9): what each
// detects, within what time, and the answer the chapter's table gives.
#pragma once

namespace legkit::engineering {

struct MonitorParams {
  double imu_dropout_periods = 2.0;    // a gap over this many nominal periods is a dropout
  double stuck_encoder_time = 0.1;     // [s] joint velocity exactly zero while the gyro moves
  double stuck_encoder_gyro = 0.5;     // [rad/s] "the IMU moves"
  double force_drift_window = 2.0;     // [s] mean force innovation window
  double force_drift_sigma = 3.0;      // persistent bias beyond this many sigma: inflate R
  double exteroception_timeout = 5.0;  // [s] without any exteroceptive update: alarm
  double position_sigma_max = 10.0;    // [m] covariance growth alarm
  double velocity_sigma_max = 5.0;     // [m/s]
};

}  // namespace legkit::engineering
