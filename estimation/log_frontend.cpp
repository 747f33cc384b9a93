#include "estimation/log_frontend.hpp"

#include <stdexcept>

namespace legkit {

LogFrontend::LogFrontend(const io::LogLayout& layout, const model::QuadrupedKinematics& kinematics,
                         const FrontendNoise& noise)
    : layout_(layout), kinematics_(kinematics), noise_(noise) {
  if (!layout.joints && layout.foot_columns == io::FootCovariance::kNone) {
    throw std::invalid_argument("LogFrontend: the log has neither joint nor foot columns");
  }
}

StepInput LogFrontend::input(const io::LogRow& row, double dt) const {
  StepInput in;
  in.t = row.t;
  in.dt = dt;
  in.imu = {row.gyro, row.acc};
  in.has_force = layout_.force;
  if (!layout_.contact) return in;

  const double var_q = noise_.encoder_angle_sigma * noise_.encoder_angle_sigma;
  const double var_foot = noise_.foot_point_sigma * noise_.foot_point_sigma;
  for (int foot = 0; foot < layout_.num_feet; ++foot) {
    if (!row.contact[foot]) continue;
    ContactMeasurement& c = in.contacts[in.num_contacts];
    c.foot = foot;
    if (layout_.joints) {
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
