#include "estimation/log_frontend.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "estimation/imu_extrinsic_frames.hpp"

namespace legkit {

FootVelocityDifferentiator::FootVelocityDifferentiator(double tau) : tau_(tau) {
  if (!(tau >= 0.0) || !std::isfinite(tau)) {
    throw std::invalid_argument("FootVelocityDifferentiator: tau must be >= 0 and finite, got " +
                                std::to_string(tau));
  }
}

void FootVelocityDifferentiator::reset() {
  p_previous_.fill(std::nullopt);
  v_.fill(std::nullopt);
  down_.fill(false);
  samples_.fill(0);
}

void FootVelocityDifferentiator::update(const std::array<Eigen::Vector3d, io::kMaxFeet>& p,
                                        const std::array<bool, io::kMaxFeet>& down, int num_feet,
                                        double dt) {
  for (int foot = 0; foot < num_feet; ++foot) {
    const bool touchdown = down[foot] && !down_[foot];
    down_[foot] = down[foot];
    if (p_previous_[foot] && dt > 0.0) {
      const Eigen::Vector3d y = (p[foot] - *p_previous_[foot]) / dt;  // backward difference
      if (touchdown || !v_[foot]) {
        v_[foot] = y;  // spans the last swing interval: forgotten at the next row
        samples_[foot] = 0;
      } else {
        // The mean of the differences since touchdown until it has tau's memory, then the low
        // pass: weight max(dt / (tau + dt), 1 / n).
        ++samples_[foot];
        const double weight = std::max(dt / (tau_ + dt), 1.0 / samples_[foot]);
        *v_[foot] += weight * (y - *v_[foot]);
      }
    }
    p_previous_[foot] = p[foot];
  }
}

namespace {

void checkLegs(const io::LogLayout& layout, const model::LegKinematics& legs) {
  if (layout.num_joints <= 0) {
    throw std::invalid_argument(
        "LogFrontend: a LegKinematics is for logs with generic joint columns (joint<k>_q), and "
        "this log has none");
  }
  if (legs.numJoints() != layout.num_joints || legs.numFeet() != layout.num_feet) {
    throw std::invalid_argument("LogFrontend: the log has " + std::to_string(layout.num_joints) +
                                " joints and " + std::to_string(layout.num_feet) +
                                " feet, the robot's kinematics " +
                                std::to_string(legs.numJoints()) + " joints and " +
                                std::to_string(legs.numFeet()) + " feet");
  }
}

}  // namespace

LogFrontend::LogFrontend(const io::LogLayout& layout, const model::QuadrupedKinematics& kinematics,
                         const FrontendNoise& noise, const model::ImuExtrinsic& extrinsic)
    : layout_(layout),
      kinematics_(kinematics),
      noise_(noise),
      extrinsic_(extrinsic),
      moves_feet_(!extrinsic.isIdentity()) {
  if (layout.num_joints > 0) {
    throw std::invalid_argument(
        "LogFrontend: the log has generic joint columns (joint<k>_q): give the robot's "
        "LegKinematics (settings robot:), not the quadruped's");
  }
  if (!layout.joints && layout.foot_columns == io::FootCovariance::kNone) {
    throw std::invalid_argument("LogFrontend: the log has neither joint nor foot columns");
  }
  if (noise.foot_rotations) {
    throw std::invalid_argument(
        "feet.flat: the feet's orientation comes from the robot's own model (robot.model, with "
        "the log's joint<k>_q columns); the built-in quadruped's feet and a log's foot columns "
        "are points");
  }
}

LogFrontend::LogFrontend(const io::LogLayout& layout, const model::LegKinematics& legs,
                         const FrontendNoise& noise, const model::ImuExtrinsic& extrinsic)
    : layout_(layout),
      legs_(&legs),
      noise_(noise),
      extrinsic_(extrinsic),
      moves_feet_(!extrinsic.isIdentity()) {
  checkLegs(layout, legs);
  Eigen::Matrix3d R_BF;
  model::FootJacobian J_w;
  if (noise.foot_rotations && !legs.footRotation(0, model::LegJointVector::Zero(), R_BF, J_w)) {
    throw std::invalid_argument(
        "feet.flat: the robot's kinematics give no foot orientation (its feet are points)");
  }
}

StepInput LogFrontend::imuInput(const io::LogRow& row, double dt) const {
  StepInput in;
  in.t = row.t;
  in.dt = dt;
  in.imu = {row.gyro, row.acc};
  in.has_force = layout_.force;
  return in;
}

ContactMeasurement LogFrontend::baseMeasurement(const io::LogRow& row, int foot) const {
  ContactMeasurement c;
  c.foot = foot;
  const double var_q = noise_.encoder_angle_sigma * noise_.encoder_angle_sigma;
  const double var_foot = noise_.foot_point_sigma * noise_.foot_point_sigma;
  if (layout_.joints) {
    const Eigen::Vector3d q = row.q.segment<3>(3 * foot);
    const Eigen::Matrix3d J = kinematics_.footJacobian(foot, q);
    c.p_body = kinematics_.footPosition(foot, q);
    c.v_body = J * row.dq.segment<3>(3 * foot);  // foot velocity relative to the body
    c.cov = var_q * J * J.transpose() + var_foot * Eigen::Matrix3d::Identity();
  } else if (legs_ != nullptr) {
    model::FootJacobian J;
    Eigen::Vector3d p;
    legs_->foot(foot, row.joint_q, p, J);  // columns >= numJoints() are zero
    c.p_body = p;
    c.v_body = J * row.joint_dq;  // J dq
    c.cov = var_q * J * J.transpose() + var_foot * Eigen::Matrix3d::Identity();
    if (noise_.foot_rotations) {
      Eigen::Matrix3d R_BF;
      legs_->footRotation(foot, row.joint_q, R_BF, J);  // the constructor checked it has them
      const double var_sole = noise_.foot_rotation_sigma * noise_.foot_rotation_sigma;
      c.R_body = R_BF;
      // n in the foot frame: R_BF^T J_w dq is the foot's rotation error for angle errors dq.
      const Eigen::Matrix<double, 3, model::kMaxLegJoints> J_F = R_BF.transpose() * J;
      c.rot_cov = var_q * J_F * J_F.transpose() + var_sole * Eigen::Matrix3d::Identity();
    }
  } else {
    c.p_body = row.feet[foot].p_body;
    c.cov = row.feet[foot].cov;
    if (layout_.foot_velocity) {
      c.v_body = row.feet[foot].v_body;
    } else {
      c.v_body.reset();
    }
  }
  return c;
}

ContactMeasurement LogFrontend::measurement(const io::LogRow& row, int foot,
                                            const FootVelocityDifferentiator* velocities) const {
  ContactMeasurement c = baseMeasurement(row, foot);
  if (moves_feet_) {
    c.p_body = pointInImu(extrinsic_, c.p_body);
    c.cov = covarianceInImu(extrinsic_, c.cov);
    if (c.v_body) c.v_body = vectorInImu(extrinsic_, *c.v_body);
    // R_IF = R_BI^T R_BF; rot_cov is in the foot's own frame and stays.
    if (c.R_body) c.R_body = extrinsic_.q_BI.toRotationMatrix().transpose() * *c.R_body;
  }
  if (velocities != nullptr && differentiatesFeet()) c.v_body = velocities->velocity(foot);
  return c;
}

void LogFrontend::differentiate(const io::LogRow& row, double dt,
                                const std::array<bool, io::kMaxFeet>& down,
                                FootVelocityDifferentiator* velocities) const {
  if (velocities == nullptr || !differentiatesFeet()) return;
  std::array<Eigen::Vector3d, io::kMaxFeet> p;
  for (int foot = 0; foot < layout_.num_feet; ++foot) {
    p[foot] = moves_feet_ ? pointInImu(extrinsic_, row.feet[foot].p_body) : row.feet[foot].p_body;
  }
  velocities->update(p, down, layout_.num_feet, dt);
}

StepInput LogFrontend::input(const io::LogRow& row, double dt,
                             FootVelocityDifferentiator* velocities) const {
  StepInput in = imuInput(row, dt);
  std::array<bool, io::kMaxFeet> down{};
  if (layout_.contact) std::copy(row.contact.begin(), row.contact.end(), down.begin());
  differentiate(row, dt, down, velocities);
  if (!layout_.contact) return in;
  for (int foot = 0; foot < layout_.num_feet; ++foot) {
    if (!row.contact[foot]) continue;
    in.contacts[in.num_contacts] = measurement(row, foot, velocities);
    in.normal_force[in.num_contacts] = row.force[foot];
    ++in.num_contacts;
  }
  return in;
}

contact::ContactSignals LogFrontend::signals(const io::LogRow& row, double dt,
                                             const contact::BaseFeedback& base) const {
  contact::ContactSignals s;
  s.t = row.t;
  s.dt = dt;
  s.num_feet = layout_.num_feet;
  s.gyro = row.gyro;
  s.acc = row.acc;
  s.base = base;
  s.has_joints = layout_.joints;
  s.has_torque = layout_.torque;
  if (layout_.joints) {
    s.q = row.q;
    s.dq = row.dq;
  }
  if (layout_.torque) s.tau = row.tau;
  const bool kinematics = layout_.joints || legs_ != nullptr || layout_.foot_velocity;
  for (int foot = 0; foot < layout_.num_feet; ++foot) {
    contact::FootSignals& f = s.feet[foot];
    if (layout_.force) f.force = row.force[foot];  // else NaN: no sensor
    if (!kinematics) continue;
    const ContactMeasurement c = measurement(row, foot, nullptr);
    f.has_kinematics = true;
    f.p_body = c.p_body;   // FK(q), in the IMU frame
    f.v_body = *c.v_body;  // J(q) dq, in the IMU frame
  }
  return s;
}

StepInput LogFrontend::input(const io::LogRow& row, double dt,
                             const contact::ContactEstimate& contacts,
                             const contact::SoftContactParams& soft,
                             FootVelocityDifferentiator* velocities) const {
  StepInput in = imuInput(row, dt);
  const int num_feet = std::min(contacts.num_feet, layout_.num_feet);
  std::array<bool, io::kMaxFeet> down{};
  for (int foot = 0; foot < num_feet; ++foot) {
    down[foot] = contacts.feet[foot].usable() && contacts.feet[foot].contact;
  }
  differentiate(row, dt, down, velocities);
  for (int foot = 0; foot < num_feet; ++foot) {
    const contact::FootContact& answer = contacts.feet[foot];
    if (!answer.usable() || !answer.contact || answer.probability < soft.min_probability) continue;
    ContactMeasurement c = measurement(row, foot, velocities);
    c.cov = contact::softMeasurementCov(c.cov, answer.probability, soft);
    c.probability = answer.probability;
    in.contacts[in.num_contacts] = c;
    in.normal_force[in.num_contacts] = row.force[foot];
    ++in.num_contacts;
  }
  return in;
}

std::vector<StepInput> LogFrontend::inputs(const io::Log& log) const {
  std::vector<StepInput> result;
  result.reserve(log.rows.size());
  FootVelocityDifferentiator velocities;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    result.push_back(
        input(log.rows[k], k == 0 ? 0.0 : log.rows[k].t - log.rows[k - 1].t, &velocities));
  }
  return result;
}

}  // namespace legkit
