// Your solution to the capstone 57.11: the four pieces, then the manager. Replace each throw with
// your implementation (the order of the tests: KF, Schmitt trigger, leg odometry, manager).
#include <legkit/not_implemented.hpp>

#include "contact_detector.hpp"
#include "leg_odometry.hpp"
#include "linear_kf.hpp"
#include "state_estimator.hpp"

namespace ex57_11 {

// ---- 1. the linear KF (linear_kf.hpp) ----------------------------------------------------------

LinearKf::LinearKf(const KfNoise& noise) : noise_(noise) {}

void LinearKf::reset(const Vector18& x0, const Matrix18& P0) {
  x_ = x0;
  P_ = P0;
}

void LinearKf::predict(double /*dt*/, const Eigen::Vector3d& /*a_w*/, const Stance& /*stance*/) {
  throw legkit::NotImplemented("LinearKf::predict");
}

void LinearKf::update(const Eigen::Vector3d& /*z*/, const Matrix3x18& /*H*/,
                      const Eigen::Matrix3d& /*R*/) {
  throw legkit::NotImplemented("LinearKf::update");
}

void LinearKf::updateFoot(int /*i*/, const Eigen::Vector3d& /*z*/) {
  throw legkit::NotImplemented("LinearKf::updateFoot");
}

void LinearKf::updateVelocity(const Eigen::Vector3d& /*v*/) {
  throw legkit::NotImplemented("LinearKf::updateVelocity");
}

// ---- 2. the Schmitt trigger (contact_detector.hpp) ---------------------------------------------

SchmittContactDetector::SchmittContactDetector(const SchmittConfig& config) : config_(config) {}

void SchmittContactDetector::reset() {
  contact_.fill(false);
  held_.fill(0.0);
}

const std::array<bool, 4>& SchmittContactDetector::update(const std::array<double, 4>& /*force*/,
                                                          double /*dt*/) {
  throw legkit::NotImplemented("SchmittContactDetector::update");
}

// ---- 3. leg odometry (leg_odometry.hpp) --------------------------------------------------------

Eigen::Vector3d footBaseVelocity(const legkit::model::QuadrupedKinematics& /*kin*/, int /*leg*/,
                                 const Eigen::Matrix3d& /*R*/, const Eigen::Vector3d& /*w*/,
                                 const legkit::io::JointVector& /*q*/,
                                 const legkit::io::JointVector& /*dq*/) {
  throw legkit::NotImplemented("footBaseVelocity");
}

LegVelocity legOdometry(const legkit::model::QuadrupedKinematics& /*kin*/,
                        const Eigen::Matrix3d& /*R*/, const Eigen::Vector3d& /*w*/,
                        const legkit::io::JointVector& /*q*/, const legkit::io::JointVector& /*dq*/,
                        const std::array<bool, 4>& /*stance*/) {
  throw legkit::NotImplemented("legOdometry");
}

// ---- 4. the manager (state_estimator.hpp) ------------------------------------------------------

StateEstimator::StateEstimator(const ManagerConfig& config, const Eigen::Quaterniond& q0,
                               const Eigen::Vector3d& v0, const Eigen::Vector3d& p0)
    : config_(config), attitude_(config.attitude), kf_(config.kf), detector_(config.schmitt) {
  state_.q = q0;
  state_.v = v0;
  state_.p = p0;
}

const BaseState& StateEstimator::update(const ImuSample& /*imu*/, const JointSample& /*joints*/,
                                        const ForceSample& /*forces*/) {
  throw legkit::NotImplemented("StateEstimator::update");
}

}  // namespace ex57_11
