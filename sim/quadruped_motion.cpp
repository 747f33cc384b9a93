#include "sim/quadruped_motion.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sim/jet.hpp"

namespace legkit::sim {
namespace {

Scenario startedAtStand(Scenario s) {
  s.gait.start = s.stand_time;
  return s;
}

Eigen::Matrix3d yawRotation(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// 64 s^3 (1 - s)^3: a lift that is 1 at mid-swing and has zero rate and acceleration at both
// ends; its derivatives with respect to s are 192 s^2 (1-s)^2 (1-2s) and
// 384 s (1-s) ((1-2s)^2 - s (1-s)).
Jet liftProfile(double s, double T) {
  const double r = 1.0 - s;
  return {64.0 * s * s * s * r * r * r, 192.0 * s * s * r * r * (1.0 - 2.0 * s) / T,
          384.0 * s * r * ((1.0 - 2.0 * s) * (1.0 - 2.0 * s) - s * r) / (T * T)};
}

}  // namespace

QuadrupedMotion::QuadrupedMotion(const Scenario& scenario,
                                 const model::QuadrupedKinematics& kinematics,
                                 const SlipFault& slip)
    : scenario_(startedAtStand(scenario)), base_(scenario_), kinematics_(kinematics), slip_(slip) {
  if (slip_.leg >= model::kNumLegs) {
    throw std::invalid_argument("slip fault: leg " + std::to_string(slip_.leg) +
                                " is out of range (0..3: FL, FR, RL, RR)");
  }
  slip_.direction.z() = 0.0;
  if (slip_.leg >= 0) {
    if (slip_.direction.norm() == 0.0) {
      throw std::invalid_argument("slip fault: the direction needs a horizontal component");
    }
    slip_.direction.normalize();
  }
  const model::QuadrupedGeometry& g = kinematics_.geometry();
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    nominal_[leg] = {g.hip_offset[leg].x(),
                     g.hip_offset[leg].y() + model::lateralSign(leg) * g.abduction_offset, 0.0};
  }
}

Eigen::Vector3d QuadrupedMotion::foothold(int leg, int index) const {
  const double t = index == 0 ? 0.0
                              : 0.5 * (touchdownTime(scenario_.gait, leg, index) +
                                       liftoffTime(scenario_.gait, leg, index));
  const BaseState b = base_.at(t);
  Eigen::Vector3d p = Eigen::Vector3d(b.p.x(), b.p.y(), 0.0) + yawRotation(b.yaw) * nominal_[leg];
  p.z() = kinematics_.geometry().foot_radius;
  return p;
}

Eigen::Vector3d QuadrupedMotion::slipDisplacement(int leg, double from, double t) const {
  if (leg != slip_.leg) return Eigen::Vector3d::Zero();
  const double begin = std::max(from, slip_.start);
  const double end = std::min(t, slip_.start + slip_.duration);
  return slip_.direction * slip_.speed * std::max(end - begin, 0.0);
}

Eigen::Vector3d QuadrupedMotion::slipVelocity(int leg, double t) const {
  const bool sliding = leg == slip_.leg && t >= slip_.start && t < slip_.start + slip_.duration;
  return sliding ? Eigen::Vector3d(slip_.direction * slip_.speed) : Eigen::Vector3d::Zero();
}

FootState QuadrupedMotion::foot(int leg, double t) const {
  const GaitPhase phase = gaitPhase(scenario_.gait, leg, t);
  FootState f;
  if (phase.stance) {
    f.contact = true;
    f.p = foothold(leg, phase.index) + slipDisplacement(leg, phase.begin, t);
    f.v = slipVelocity(leg, t);
    return f;
  }
  // Swing `index`: from where stance `index` ended to the foothold of stance `index + 1`.
  f.contact = false;
  const double T = phase.end - phase.begin;
  const double u = t - phase.begin;
  const double stance_begin =
      phase.index == 0 ? -INFINITY : touchdownTime(scenario_.gait, leg, phase.index);
  const Eigen::Vector3d p0 =
      foothold(leg, phase.index) + slipDisplacement(leg, stance_begin, phase.begin);
  const Eigen::Vector3d v0 = slipVelocity(leg, phase.begin);
  const Eigen::Vector3d p1 = foothold(leg, phase.index + 1);
  for (int i = 0; i < 3; ++i) {
    const Jet c = quinticHermite(p0(i), v0(i), 0.0, p1(i), 0.0, 0.0, T, u);
    f.p(i) = c.f;
    f.v(i) = c.d;
  }
  const Jet lift = liftProfile(u / T, T);
  f.p.z() += scenario_.swing_height * lift.f;
  f.v.z() += scenario_.swing_height * lift.d;
  return f;
}

JointState QuadrupedMotion::joints(int leg, const BaseState& base, const FootState& foot) const {
  JointState j;
  j.p_body = base.R.transpose() * (foot.p - base.p);
  j.v_body = base.R.transpose() * (foot.v - base.v) - base.w.cross(j.p_body);
  j.q = kinematics_.inverseKinematics(leg, j.p_body);
  j.dq = kinematics_.footJacobian(leg, j.q).partialPivLu().solve(j.v_body);
  return j;
}

}  // namespace legkit::sim
