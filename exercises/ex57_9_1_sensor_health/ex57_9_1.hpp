// Exercise 57.9.1: a sensor-health monitor for the IMU, the joint encoders and the foot force
// sensors: what counts as a fault, and what the estimator does about each.
#pragma once

#include <array>

#include "io/log.hpp"

namespace ex57_9_1 {

enum class Fault {
  kImuDropout,       // the IMU stream has a gap
  kImuSaturation,    // a gyro or accelerometer axis at its range
  kEncoderJump,      // a joint angle moves by more than is physically possible in one step
  kEncoderFrozen,    // a joint angle stops changing at all
  kForceSaturation,  // a foot force at the sensor's range
  kForceDrift,       // a foot force sensor's offset has drifted (it reads load in swing)
};
constexpr int kNumFaults = 6;

// What the estimator does with a sample while a fault is active.
enum class Response {
  kIgnoreSample,  // drop the faulty measurement for this step, keep running
  kHold,          // carry the last good value through (predict with it)
  kInflateR,      // keep the measurement, with its noise covariance R scaled up
  kAlarm,         // stop trusting the sensor and tell the operator / the controller
};

Response responseTo(Fault fault);

// The sensors' ranges (the Go2's class of hardware): a reading at 99 % of a range or more is
// saturated.
constexpr double kGyroRange = 34.9;    // [rad/s] (2000 deg/s)
constexpr double kAccelRange = 156.9;  // [m/s^2] (16 g)
constexpr double kForceRange = 400.0;  // [N]

struct Thresholds {
  double imu_max_gap = 0.0;          // a time step above this is a dropout [s]
  double encoder_max_step = 0.0;     // a joint angle change above this in one row is a jump [rad]
  double encoder_frozen_time = 0.0;  // a joint angle exactly unchanged this long is frozen [s]
  double force_drift = 0.0;          // a swing-phase force (low-passed) above this is drift [N]
  double force_drift_tau = 0.0;      // the low-pass time constant of the swing force [s]
};

// Your thresholds for a 1 kHz Go2-class robot, justified in answer.md.
Thresholds defaultThresholds();

// The monitor's state after one row: which faults are active (indexed by Fault).
using Report = std::array<bool, kNumFaults>;

class SensorMonitor {
 public:
  explicit SensorMonitor(const Thresholds& thresholds);
  // One log row of the quadruped layout (IMU, 12 joints q, 4 foot forces, 4 contact flags from the
  // gait schedule: a flag at 0 means the foot should be in the air). A fault is active on the row
  // where its condition holds:
  //   kImuDropout       t - t_prev > imu_max_gap (never on the first row);
  //   kImuSaturation    an axis |gyro_i| >= 0.99 kGyroRange or |accel_i| >= 0.99 kAccelRange;
  //   kEncoderJump      some |q_j - q_j,prev| > encoder_max_step;
  //   kEncoderFrozen    some q_j exactly equal to its value of encoder_frozen_time ago and every
  //   row
  //                     since (rows where it last changed: t - t_change >= encoder_frozen_time);
  //   kForceSaturation  some force >= 0.99 kForceRange;
  //   kForceDrift       some foot's low-passed swing force |f_lp| > force_drift, where on each row
  //                     with its flag at 0: f_lp += (1 - exp(-dt / tau)) (f - f_lp) (f_lp starts at
  //                     0 and holds in stance).
  const Report& update(const legkit::io::LogRow& row);

 private:
  Thresholds th_;
  Report report_{};
  bool first_ = true;
  double t_prev_ = 0.0;
  legkit::io::JointVector q_prev_ = legkit::io::JointVector::Zero();
  std::array<double, 12> t_change_{};
  std::array<double, 4> f_lp_{};
};

}  // namespace ex57_9_1
