#include "estimation/contact/foot_force.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace legkit::contact {

double jacobianRatio(const Eigen::Matrix3d& J) {
  const double lengths = J.col(0).norm() * J.col(1).norm() * J.col(2).norm();
  return lengths > 0.0 ? std::abs(J.determinant()) / lengths : 0.0;
}

FootForceFromTorque::FootForceFromTorque(const model::QuadrupedGeometry& geometry,
                                         const model::QuadrupedInertia& inertia,
                                         const FootForceParams& params)
    : dynamics_(geometry, inertia, params.gravity), params_(params), damping_(inertia.damping) {
  if (!(params.min_jacobian_ratio >= 0.0 && params.min_jacobian_ratio < 1.0))
    throw std::invalid_argument("FootForceFromTorque: min_jacobian_ratio = " +
                                std::to_string(params.min_jacobian_ratio) + " outside [0, 1)");
}

bool FootForceFromTorque::state(const ContactSignals& s, model::FloatingBaseState& x) const {
  if (s.base.valid) {
    x.R = s.base.R;
    x.v = s.base.v;
  } else {
    // A robot at rest measures a = R^T (0, 0, g): the body-frame up direction u. With yaw 0,
    // R = Ry(pitch) Rx(roll) and its third row (R^T e_z) is (-sin pitch, cos pitch sin roll,
    // cos pitch cos roll) = u.
    const double g = s.acc.norm();
    if (!std::isfinite(g) || g < 0.1 * params_.gravity) return false;
    const Eigen::Vector3d u = s.acc / g;
    const double pitch = std::asin(std::clamp(-u.x(), -1.0, 1.0));
    const double roll = std::atan2(u.y(), u.z());
    x.R = (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
              .toRotationMatrix();
    x.v.setZero();
  }
  x.p.setZero();  // h does not depend on the position
  x.omega = s.gyro;
  x.q = s.q;
  x.dq = s.dq;
  return true;
}

std::array<Eigen::Vector3d, model::kNumLegs> FootForceFromTorque::estimate(
    const ContactSignals& s, std::array<const char*, model::kNumLegs>* problems) const {
  std::array<Eigen::Vector3d, model::kNumLegs> lambda;
  std::array<const char*, model::kNumLegs> why{};
  const char* all = nullptr;  // a reason that holds for every leg
  if (!s.has_joints)
    all = "no joint angles";
  else if (!s.has_torque)
    all = "no joint torques";
  else if (s.num_feet != model::kNumLegs)
    all = "joints not the quadruped's";
  else if (!s.gyro.allFinite() || (s.base.valid && !(s.base.R.allFinite() && s.base.v.allFinite())))
    all = "base state not finite";

  model::FloatingBaseState x;
  if (all == nullptr && !state(s, x)) all = "no attitude";
  model::GeneralizedVector h = model::GeneralizedVector::Zero();
  if (all == nullptr) {
    // A leg's rows of h depend on the base and that leg only: a leg with a non-finite joint
    // state enters h with zeros (it gets its problem below), the others are unaffected.
    for (int l = 0; l < model::kNumLegs; ++l)
      if (!(s.q.segment<3>(3 * l).allFinite() && s.dq.segment<3>(3 * l).allFinite())) {
        x.q.segment<3>(3 * l).setZero();
        x.dq.segment<3>(3 * l).setZero();
      }
    h = dynamics_.biasForces(x);
  }

  const model::QuadrupedKinematics& kin = dynamics_.kinematics();
  for (int l = 0; l < model::kNumLegs; ++l) {
    lambda[l].setConstant(std::numeric_limits<double>::quiet_NaN());
    if (all != nullptr) {
      why[l] = all;
      continue;
    }
    const Eigen::Vector3d q = s.q.segment<3>(3 * l), dq = s.dq.segment<3>(3 * l);
    const Eigen::Vector3d tau = s.tau.segment<3>(3 * l);
    if (!(q.allFinite() && dq.allFinite())) {
      why[l] = "joint state not finite";
      continue;
    }
    if (!tau.allFinite()) {
      why[l] = "joint torque not finite";
      continue;
    }
    const Eigen::Matrix3d J_body = kin.footJacobian(l, q);
    if (jacobianRatio(J_body) < params_.min_jacobian_ratio) {
      why[l] = "leg singular";
      continue;
    }
    // lambda_l = (R B_J)^-T (h_l - tau_l) = R B_J^-T (h_l - tau_l), tau_l = motor - D dq_l
    const Eigen::Vector3d rhs = h.segment<3>(6 + 3 * l) - (tau - damping_.cwiseProduct(dq));
    lambda[l] = x.R * J_body.transpose().partialPivLu().solve(rhs);
  }
  if (problems != nullptr) *problems = why;
  return lambda;
}

}  // namespace legkit::contact
