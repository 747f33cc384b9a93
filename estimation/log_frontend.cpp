#include "estimation/log_frontend.hpp"

#include <algorithm>
#include <stdexcept>

namespace legkit {

LogFrontend::LogFrontend(const io::LogLayout& layout, const model::QuadrupedKinematics& kinematics,
                         const FrontendNoise& noise)
    : layout_(layout), kinematics_(kinematics), noise_(noise) {
  if (!layout.joints && layout.foot_columns == io::FootCovariance::kNone) {
    throw std::invalid_argument("LogFrontend: the log has neither joint nor foot columns");
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

ContactMeasurement LogFrontend::measurement(const io::LogRow& row, int foot) const {
  ContactMeasurement c;
  c.foot = foot;
  if (layout_.joints) {
    const double var_q = noise_.encoder_angle_sigma * noise_.encoder_angle_sigma;
    const double var_foot = noise_.foot_point_sigma * noise_.foot_point_sigma;
    const Eigen::Vector3d q = row.q.segment<3>(3 * foot);
    const Eigen::Matrix3d J = kinematics_.footJacobian(foot, q);
    c.p_body = kinematics_.footPosition(foot, q);
    c.v_body = J * row.dq.segment<3>(3 * foot);  // foot velocity relative to the body
    c.cov = var_q * J * J.transpose() + var_foot * Eigen::Matrix3d::Identity();
  } else {
    c.p_body = row.feet[foot].p_body;
    c.cov = row.feet[foot].cov;
    c.v_body.reset();
  }
  return c;
}

StepInput LogFrontend::input(const io::LogRow& row, double dt) const {
  StepInput in = imuInput(row, dt);
  if (!layout_.contact) return in;
  for (int foot = 0; foot < layout_.num_feet; ++foot) {
    if (!row.contact[foot]) continue;
    in.contacts[in.num_contacts] = measurement(row, foot);
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
  for (int foot = 0; foot < layout_.num_feet; ++foot) {
    contact::FootSignals& f = s.feet[foot];
    if (layout_.force) f.force = row.force[foot];  // else NaN: no sensor
    if (!layout_.joints) continue;
    const Eigen::Vector3d q = row.q.segment<3>(3 * foot);
    f.has_kinematics = true;
    f.p_body = kinematics_.footPosition(foot, q);                                // FK(q)
    f.v_body = kinematics_.footJacobian(foot, q) * row.dq.segment<3>(3 * foot);  // J(q) dq
  }
  return s;
}

StepInput LogFrontend::input(const io::LogRow& row, double dt,
                             const contact::ContactEstimate& contacts,
                             const contact::SoftContactParams& soft) const {
  StepInput in = imuInput(row, dt);
  const int num_feet = std::min(contacts.num_feet, layout_.num_feet);
  for (int foot = 0; foot < num_feet; ++foot) {
    const contact::FootContact& answer = contacts.feet[foot];
    if (!answer.usable() || !answer.contact || answer.probability < soft.min_probability) continue;
    ContactMeasurement c = measurement(row, foot);
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
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    result.push_back(input(log.rows[k], k == 0 ? 0.0 : log.rows[k].t - log.rows[k - 1].t));
  }
  return result;
}

}  // namespace legkit
