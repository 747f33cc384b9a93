#include "estimation/leg_odometry/rolling_foot.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace legkit::leg_odometry {

RollingFoot::RollingFoot(const model::QuadrupedGeometry& geometry) : r_(geometry.foot_radius) {
  if (!(std::isfinite(r_) && r_ >= 0.0)) {
    throw std::invalid_argument("RollingFoot: foot_radius must be finite and non-negative");
  }
  reset();
}

void RollingFoot::reset() {
  stance_.fill(false);
  for (int i = 0; i < kFeet; ++i) {
    s_[i].setZero();
    v_roll_[i].setZero();
  }
}

void RollingFoot::apply(StepInput& in, const Eigen::Matrix3d& R, const Eigen::Vector3d& w,
                        const io::JointVector& q, const io::JointVector& dq) {
  for (const ContactMeasurement& c : in.stance()) {
    if (c.foot < 0 || c.foot >= kFeet) {
      throw std::invalid_argument("RollingFoot::apply at t = " + std::to_string(in.t) +
                                  ": foot id " + std::to_string(c.foot) +
                                  " is not a quadruped foot (0..3)");
    }
    if (!c.v_body) {
      throw std::invalid_argument("RollingFoot::apply at t = " + std::to_string(in.t) +
                                  ": foot id " + std::to_string(c.foot) +
                                  " has no v_body (the centre's velocity J dq)");
    }
  }
  const Eigen::Vector3d rn_b = r_ * R.row(2).transpose();  // r n_b = r R^T e_z
  std::array<bool, kFeet> stance{};
  for (int k = 0; k < in.num_contacts; ++k) {
    ContactMeasurement& c = in.contacts[k];
    const int i = c.foot;
    stance[i] = true;
    // w_leg = dq1 e_x + Rx(q1) (dq2 + dq3) e_y: the calf's rate relative to the body.
    const double q1 = q[3 * i], dq1 = dq[3 * i], dq23 = dq[3 * i + 1] + dq[3 * i + 2];
    const Eigen::Vector3d w_leg(dq1, std::cos(q1) * dq23, std::sin(q1) * dq23);
    // v_roll = w_calf x (r n) in the world, w_calf = R (w + w_leg).
    const Eigen::Vector3d v_roll = R * (w + w_leg).cross(rn_b);
    if (!stance_[i]) {  // touchdown: the rolled distance starts over
      s_[i].setZero();
    } else {
      s_[i] += 0.5 * in.dt * (v_roll_[i] + v_roll);  // trapezoidal rule
    }
    v_roll_[i] = v_roll;
    const Eigen::Vector3d s_b = R.transpose() * s_[i];
    c.p_body -= rn_b + s_b;                         // p_body' = c_b - r n_b - s_b
    *c.v_body += w.cross(s_b) - w_leg.cross(rn_b);  // v_body' = v_c + w x s_b - w_leg x r n_b
  }
  for (int i = 0; i < kFeet; ++i) {
    if (!stance[i]) s_[i].setZero();
  }
  stance_ = stance;
}

}  // namespace legkit::leg_odometry
