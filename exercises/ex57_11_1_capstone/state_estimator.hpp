// Capstone 57.11.1, piece 4: the manager that ties the pieces together, what a controller calls at
// the IMU rate.
#pragma once

#include <Eigen/Geometry>
#include <array>

#include "contact_detector.hpp"
#include "estimation/linear_kf/attitude_filter.hpp"
#include "io/log.hpp"
#include "leg_odometry.hpp"
#include "linear_kf.hpp"
#include "model/quadruped.hpp"

namespace ex57_11 {

struct ImuSample {
  double t = 0.0;                                  // [s]
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();  // w_m [rad/s]
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();   // a_m, specific force [m/s^2]
};
struct JointSample {
  legkit::io::JointVector q = legkit::io::JointVector::Zero();   // [rad]
  legkit::io::JointVector dq = legkit::io::JointVector::Zero();  // [rad/s]
};
struct ForceSample {
  std::array<double, 4> force{};  // normal force per foot [N]
};

struct BaseState {
  double t = 0.0;
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // body to world
  Eigen::Vector3d v = Eigen::Vector3d::Zero();            // [m/s, world]
  Eigen::Vector3d p = Eigen::Vector3d::Zero();            // [m, world]
  std::array<bool, 4> contact{};                          // the detector's stance flags
};

struct ManagerConfig {
  KfNoise kf;
  SchmittConfig schmitt;
  legkit::linear_kf::AttitudeFilterParams attitude;  // the kit's attitude filter (not a piece)
  double foot_init_sigma = 1.0;                      // the feet's prior, per axis [m]
  double p_sigma = 0.01, v_sigma = 0.05;             // the base's prior, per axis [m], [m/s]
};

// The chapter's manager. A sample k is the motion over [t_k, t_k+1) (the logs' convention), so:
//   1. dt = t_k - t_{k-1} (the first sample only sets things up: dt = 0, no prediction);
//   2. the attitude filter propagates with sample k-1's IMU reading over dt -> R_hat;
//   3. the KF predicts over dt with sample k-1's world acceleration R_hat_{k-1} a_m,k-1 + g and
//      sample k-1's stance;
//   4. the Schmitt trigger takes sample k's forces (dt; 0 on the first sample) -> stance_k;
//   5. for each stance foot: updateFoot(i, R_hat r_i); then, with at least one stance foot,
//      updateVelocity of the legs' fused velocity (w = gyro_k, R_hat);
//   6. the state: R_hat, the KF's v and p, stance_k.
// Starts from x0 (R_0, v_0, p_0) with the feet at p_0 + R_0 r_i(q of the first sample).
class StateEstimator {
 public:
  StateEstimator(const ManagerConfig& config, const Eigen::Quaterniond& q0,
                 const Eigen::Vector3d& v0, const Eigen::Vector3d& p0);
  const BaseState& update(const ImuSample& imu, const JointSample& joints,
                          const ForceSample& forces);

 private:
  ManagerConfig config_;
  legkit::model::QuadrupedKinematics kin_;
  legkit::linear_kf::AttitudeFilter attitude_;
  LinearKf kf_;
  SchmittContactDetector detector_;
  BaseState state_;
  ImuSample previous_imu_;
  Stance previous_stance_{};
  bool started_ = false;
};

}  // namespace ex57_11
