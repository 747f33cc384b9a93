// Reference solution to the capstone 57.11: the four pieces, then the manager.
#include <cmath>
#include <stdexcept>

#include "contact_detector.hpp"
#include "leg_odometry.hpp"
#include "linear_kf.hpp"
#include "model/imu_model.hpp"
#include "state_estimator.hpp"

namespace ex57_11 {

// ---- 1. the linear KF --------------------------------------------------------------------------

LinearKf::LinearKf(const KfNoise& noise) : noise_(noise) {}

void LinearKf::reset(const Vector18& x0, const Matrix18& P0) {
  x_ = x0;
  P_ = P0;
}

void LinearKf::predict(double dt, const Eigen::Vector3d& a_w, const Stance& stance) {
  if (!(dt > 0.0)) throw std::invalid_argument("LinearKf::predict: dt must be positive");
  // x+ = F x + B u: p += v dt + a dt^2/2, v += a dt.
  x_.segment<3>(0) += x_.segment<3>(3) * dt + 0.5 * dt * dt * a_w;
  x_.segment<3>(3) += dt * a_w;
  // F P F^T with F = I + dt E (E moves v into p): rows of p, then columns of p.
  P_.middleRows<3>(0) += dt * P_.middleRows<3>(3);
  P_.middleCols<3>(0) += dt * P_.middleCols<3>(3);
  // Q: the held accelerometer noise sigma_a^2 / dt through B = [dt^2/2; dt] (per axis), the feet's
  // random walks.
  const double s = noise_.accel_density * noise_.accel_density / dt;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  P_.block<3, 3>(0, 0) += s * dt * dt * dt * dt / 4.0 * I;
  P_.block<3, 3>(0, 3) += s * dt * dt * dt / 2.0 * I;
  P_.block<3, 3>(3, 0) += s * dt * dt * dt / 2.0 * I;
  P_.block<3, 3>(3, 3) += s * dt * dt * I;
  for (int i = 0; i < kFeet; ++i) {
    const double sigma = stance[i] ? noise_.foot_stance_density : noise_.foot_swing_density;
    P_.block<3, 3>(6 + 3 * i, 6 + 3 * i) += sigma * sigma * dt * I;
  }
}

void LinearKf::update(const Eigen::Vector3d& z, const Matrix3x18& H, const Eigen::Matrix3d& R) {
  const Eigen::Matrix<double, kStates, 3> PHt = P_ * H.transpose();
  const Eigen::Matrix3d S = H * PHt + R;                          // innovation covariance
  const Eigen::Matrix<double, kStates, 3> K = PHt * S.inverse();  // gain
  x_ += K * (z - H * x_);
  const Matrix18 A = Matrix18::Identity() - K * H;  // Joseph form: symmetric and PSD by build
  P_ = A * P_ * A.transpose() + K * R * K.transpose();
}

void LinearKf::updateFoot(int i, const Eigen::Vector3d& z) {
  if (i < 0 || i >= kFeet) throw std::invalid_argument("LinearKf::updateFoot: foot out of range");
  Matrix3x18 H = Matrix3x18::Zero();
  H.block<3, 3>(0, 0) = -Eigen::Matrix3d::Identity();
  H.block<3, 3>(0, 6 + 3 * i) = Eigen::Matrix3d::Identity();
  const double r = noise_.foot_position_sigma;
  update(z, H, r * r * Eigen::Matrix3d::Identity());
}

void LinearKf::updateVelocity(const Eigen::Vector3d& v) {
  Matrix3x18 H = Matrix3x18::Zero();
  H.block<3, 3>(0, 3) = Eigen::Matrix3d::Identity();
  const double r = noise_.velocity_sigma;
  update(v, H, r * r * Eigen::Matrix3d::Identity());
}

// ---- 2. the Schmitt trigger --------------------------------------------------------------------

SchmittContactDetector::SchmittContactDetector(const SchmittConfig& config) : config_(config) {
  if (!(config.f_low <= config.f_high) || !(config.t_on >= 0.0) || !(config.t_off >= 0.0))
    throw std::invalid_argument("SchmittContactDetector: need f_low <= f_high, t_on, t_off >= 0");
}

void SchmittContactDetector::reset() {
  contact_.fill(false);
  held_.fill(0.0);
}

const std::array<bool, 4>& SchmittContactDetector::update(const std::array<double, 4>& force,
                                                          double dt) {
  for (int i = 0; i < 4; ++i) {
    // The threshold that would switch the state, and how long it must hold.
    const bool beyond = contact_[i] ? force[i] < config_.f_low : force[i] > config_.f_high;
    const double T = contact_[i] ? config_.t_off : config_.t_on;
    held_[i] = beyond ? held_[i] + dt : 0.0;
    if (beyond && held_[i] > T + 1e-9) {
      contact_[i] = !contact_[i];
      held_[i] = 0.0;
    }
  }
  return contact_;
}

// ---- 3. leg odometry ---------------------------------------------------------------------------

Eigen::Vector3d footBaseVelocity(const legkit::model::QuadrupedKinematics& kin, int leg,
                                 const Eigen::Matrix3d& R, const Eigen::Vector3d& w,
                                 const legkit::io::JointVector& q,
                                 const legkit::io::JointVector& dq) {
  const Eigen::Vector3d q_i = q.segment<3>(3 * leg), dq_i = dq.segment<3>(3 * leg);
  const Eigen::Vector3d r = kin.footPosition(leg, q_i);
  return -R * (w.cross(r) + kin.footJacobian(leg, q_i) * dq_i);  // the foot does not move
}

LegVelocity legOdometry(const legkit::model::QuadrupedKinematics& kin, const Eigen::Matrix3d& R,
                        const Eigen::Vector3d& w, const legkit::io::JointVector& q,
                        const legkit::io::JointVector& dq, const std::array<bool, 4>& stance) {
  LegVelocity out;
  for (int leg = 0; leg < 4; ++leg) {
    if (!stance[leg]) continue;
    out.v += footBaseVelocity(kin, leg, R, w, q, dq);
    ++out.feet;
  }
  if (out.feet > 0) out.v /= out.feet;
  return out;
}

// ---- 4. the manager ----------------------------------------------------------------------------

StateEstimator::StateEstimator(const ManagerConfig& config, const Eigen::Quaterniond& q0,
                               const Eigen::Vector3d& v0, const Eigen::Vector3d& p0)
    : config_(config), attitude_(config.attitude), kf_(config.kf), detector_(config.schmitt) {
  attitude_.reset(lie::SO3d::fromMatrix(q0.normalized().toRotationMatrix(), 1e-9));
  state_.q = q0.normalized();
  state_.v = v0;
  state_.p = p0;
}

const BaseState& StateEstimator::update(const ImuSample& imu, const JointSample& joints,
                                        const ForceSample& forces) {
  const double dt = started_ ? imu.t - previous_imu_.t : 0.0;
  if (started_ && !(dt > 0.0))
    throw std::invalid_argument("StateEstimator::update: time must increase");
  if (!started_) {
    // The feet where the legs put them now.
    const Eigen::Matrix3d R0 = state_.q.toRotationMatrix();
    Vector18 x0 = Vector18::Zero();
    x0.segment<3>(0) = state_.p;
    x0.segment<3>(3) = state_.v;
    for (int i = 0; i < kFeet; ++i)
      x0.segment<3>(6 + 3 * i) = state_.p + R0 * kin_.footPosition(i, joints.q.segment<3>(3 * i));
    Vector18 sigma = Vector18::Constant(config_.foot_init_sigma);
    sigma.segment<3>(0).setConstant(config_.p_sigma);
    sigma.segment<3>(3).setConstant(config_.v_sigma);
    kf_.reset(x0, sigma.cwiseAbs2().asDiagonal());
  } else {
    // Sample k-1 held over [t_k-1, t_k): attitude, then the KF with its world acceleration.
    const Eigen::Matrix3d R_prev = attitude_.R().matrix();
    attitude_.propagate({previous_imu_.gyro, previous_imu_.acc}, dt);
    kf_.predict(dt, R_prev * previous_imu_.acc + legkit::model::gravity(), previous_stance_);
  }
  const Stance stance = detector_.update(forces.force, dt);
  const Eigen::Matrix3d R = attitude_.R().matrix();
  for (int i = 0; i < kFeet; ++i)
    if (stance[i]) kf_.updateFoot(i, R * kin_.footPosition(i, joints.q.segment<3>(3 * i)));
  const LegVelocity legs = legOdometry(kin_, R, imu.gyro, joints.q, joints.dq, stance);
  if (legs.feet > 0) kf_.updateVelocity(legs.v);

  state_.t = imu.t;
  state_.q = Eigen::Quaterniond(R);
  state_.v = kf_.x().segment<3>(3);
  state_.p = kf_.x().segment<3>(0);
  state_.contact = stance;
  previous_imu_ = imu;
  previous_stance_ = stance;
  started_ = true;
  return state_;
}

}  // namespace ex57_11
