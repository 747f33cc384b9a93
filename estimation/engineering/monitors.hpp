// Sensor-health and covariance monitors with graceful degradation (section 57.9): what each
// detects, within what time, and the answer the chapter's table gives.
//
//   alarm                 detected when                                   the answer
//   IMU dropout           a sample arrives more than imu_dropout_periods  the filter has held the
//                         nominal periods after the previous one          last IMU sample over the
//                                                                         gap (the estimator
//                                                                         contract's
//                                                                         extrapolation): the
//                                                                         estimate is flagged
//                                                                         uncertain
//   stuck encoder         a joint's angle is frozen (bit for bit) and its that leg's kinematics
//                         rate is 0 or frozen for stuck_encoder_time      are wrong: its contacts
//                         while the body moves (gyro or estimated speed)  are not trusted
//                                                                         (applyTo removes them)
//   force-sensor drift    the mean of (sensor - model) normal force over  inflate that sensor's
//                         force_drift_window beyond force_drift_sigma     variance
//                         sigma (the model: the force from the joint      (forceNoiseScale); a
//                         torques, or the stance share of the weight)     detector without a noise
//                                                                         model stops using it
//   exteroception lost    no exteroceptive update for                     an alarm: the estimate
//                         exteroception_timeout                           drifts as proprioception
//                                                                         alone does
//   covariance growth     a position or velocity sigma beyond its bound   a warning
//   not positive definite LDLT of P fails, or the filter recovered        an alarm (the recovery
//                         (Fault::kStateUnhealthy counted this step)      is the filter's, see
//                                                                         estimation/health.hpp)
//
// The monitor allocates nothing per update: everything it keeps is fixed-size.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>

#include "estimation/estimator.hpp"
#include "estimation/health.hpp"
#include "estimation/step_input.hpp"
#include "io/log.hpp"

namespace legkit::engineering {

struct MonitorParams {
  double imu_dropout_periods = 2.0;    // a gap over this many nominal periods is a dropout
  double stuck_encoder_time = 0.1;     // [s] joint frozen this long while the body moves
  double stuck_encoder_gyro = 0.5;     // [rad/s] "the IMU moves": |gyro| beyond this ...
  double stuck_encoder_speed = 0.1;    // [m/s] ... or the estimated speed beyond this
  double force_drift_window = 0.25;    // [s] time constant of the mean (sensor - model) force
  double force_drift_sigma = 3.0;      // persistent bias beyond this many force_sigma: drift
  double force_sigma = 3.0;            // [N] sigma of (sensor - model) per sample, healthy robot
  double exteroception_timeout = 5.0;  // [s] without any exteroceptive update: alarm
  double position_sigma_max = 10.0;    // [m] covariance growth alarm
  double velocity_sigma_max = 5.0;     // [m/s]
};

enum class Alarm : int {
  kImuDropout,
  kStuckEncoder,
  kForceDrift,
  kExteroceptionLost,
  kCovarianceGrowth,
  kNotPositiveDefinite,
  kCount
};
constexpr int kNumAlarms = static_cast<int>(Alarm::kCount);

// A short name for each alarm, for tables and messages.
const char* alarmName(Alarm a);

// What the robot measured at one step and the filter's state after it. Plain data, filled by the
// caller in place (no allocation).
struct MonitorInput {
  double t = 0.0;                                  // IMU sample time [s]
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();  // measured body rate [rad/s]
  // Joint encoders (the quadruped's 12 in joint order 3 leg + j, or generic joints): joints are
  // split evenly over the feet, leg i owning joints [i n/num_feet, (i+1) n/num_feet).
  int num_joints = 0;
  io::GenericJointVector q = io::GenericJointVector::Zero();   // [rad]
  io::GenericJointVector dq = io::GenericJointVector::Zero();  // [rad/s]
  // Normal force per foot: the sensor's reading and a model's (NaN where the model has none this
  // step: that foot's drift mean is held).
  bool has_force = false;
  std::array<double, io::kMaxFeet> force{};        // [N]
  std::array<double, io::kMaxFeet> force_model{};  // [N]
  // Exteroception (57.8): whether the robot has any, and the time of its last update (-inf when
  // none yet: the timeout then counts from the first update after reset()).
  bool has_exteroception = false;
  double exteroception_t = -std::numeric_limits<double>::infinity();
  // The filter after the step: its velocity estimate (world), covariance (null when it keeps
  // none) and health record (null when not an Estimator's).
  Eigen::Vector3d v_hat = Eigen::Vector3d::Zero();
  const BaseCovariance* P = nullptr;
  const Health* health = nullptr;
};

struct MonitorReport {
  std::array<bool, kNumAlarms> active{};
  // Since when the active alarm holds (NaN while inactive) [s].
  std::array<double, kNumAlarms> since{};
  // First and last time each alarm was active (NaN: never) [s].
  std::array<double, kNumAlarms> first{}, last{};
  std::array<std::uint64_t, kNumAlarms> count{};  // times raised (inactive -> active)
  bool uncertain = false;  // any alarm active: the estimate is extrapolated or degraded
  double imu_gap = 0.0;    // the last IMU interval [s]
  double position_sigma = 0.0, velocity_sigma = 0.0;  // largest axis sigma of P [m], [m/s]

  bool operator[](Alarm a) const { return active[static_cast<int>(a)]; }
};

class HealthMonitor {
 public:
  // Throws std::invalid_argument for num_feet outside [1, io::kMaxFeet], a nominal_dt or a
  // parameter that is not positive.
  HealthMonitor(const MonitorParams& params, int num_feet, double nominal_dt);
  void reset();

  // One step: what the robot measured and the filter's state after the step.
  const MonitorReport& update(const MonitorInput& in);
  const MonitorReport& report() const { return report_; }

  // Graceful degradation the caller applies:
  // the factor on foot i's force-sensor variance (1 healthy; while drifting 1 + (b / force_sigma)^2
  // for the mean bias b, the variance that covers it).
  double forceNoiseScale(int foot) const;
  // False while a joint of leg i is stuck: its foot's kinematics are not to be trusted.
  bool legTrusted(int foot) const;
  // Removes the contacts of untrusted legs from a filter's input; returns how many it removed.
  int applyTo(StepInput& in) const;
  // The windowed mean (sensor - model) force of foot i [N].
  double forceBias(int foot) const { return force_bias_[foot]; }

 private:
  void set(Alarm a, bool on, double t);

  MonitorParams params_;
  int num_feet_;
  double nominal_dt_;
  MonitorReport report_;
  double t_prev_ = std::numeric_limits<double>::quiet_NaN();
  double t_first_ = std::numeric_limits<double>::quiet_NaN();
  io::GenericJointVector q_prev_, dq_prev_;
  std::array<double, io::kMaxJoints> frozen_for_{};  // [s] each joint frozen for
  std::array<bool, io::kMaxJoints> moved_{};         // the body moved while it was frozen
  std::array<bool, io::kMaxFeet> leg_stuck_{};
  std::array<double, io::kMaxFeet> force_bias_{};  // windowed mean (sensor - model) [N]
  std::array<bool, io::kMaxFeet> drifting_{};
  std::uint64_t unhealthy_seen_ = 0;  // the filter's kStateUnhealthy count at the last update
};

}  // namespace legkit::engineering
