// Test support for section 57.3: a base moving rigidly over four fixed footholds, with the joint
// angles from QuadrupedKinematics::inverseKinematics and the joint rates from a central
// difference of those angles in time (so that the truth never uses the foot Jacobian).
#pragma once

#include <Eigen/Core>
#include <array>
#include <lie/so3.hpp>

#include "model/contact_measurement.hpp"
#include "model/quadruped.hpp"

namespace legkit::test {

// p(t) = p0 + v0 t + a t^2 / 2 and R(t) = R0 Exp(w_b t): constant body rate w_b.
struct StanceMotion {
  Eigen::Vector3d p0 = Eigen::Vector3d(0.0, 0.0, 0.32);
  Eigen::Vector3d v0 = Eigen::Vector3d::Zero();
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R0 = Eigen::Matrix3d::Identity();
  Eigen::Vector3d w_b = Eigen::Vector3d::Zero();
  std::array<Eigen::Vector3d, model::kNumLegs> d;  // footholds in the world

  // Footholds under a Go2 standing at (p0, R0) with joints (0, 0.8, -1.5).
  static StanceMotion standing(const model::QuadrupedKinematics& kin) {
    StanceMotion m;
    for (int leg = 0; leg < model::kNumLegs; ++leg) {
      m.d[leg] = m.p0 + m.R0 * kin.footPosition(leg, Eigen::Vector3d(0.0, 0.8, -1.5));
    }
    return m;
  }

  Eigen::Vector3d p(double t) const { return p0 + v0 * t + 0.5 * a * t * t; }
  Eigen::Vector3d v(double t) const { return v0 + a * t; }
  Eigen::Matrix3d R(double t) const {
    return R0 * lie::SO3d::Exp(Eigen::Vector3d(w_b * t)).matrix();
  }
  Eigen::Vector3d r(int leg, double t) const { return R(t).transpose() * (d[leg] - p(t)); }
  Eigen::Vector3d q(const model::QuadrupedKinematics& kin, int leg, double t) const {
    return kin.inverseKinematics(leg, r(leg, t));
  }
  Eigen::Vector3d qdot(const model::QuadrupedKinematics& kin, int leg, double t) const {
    constexpr double h = 1e-5;
    return (q(kin, leg, t + h) - q(kin, leg, t - h)) / (2.0 * h);
  }
  // What the encoders give a leg odometry: body-frame foot position FK(q) and velocity J qdot.
  ContactMeasurement contact(const model::QuadrupedKinematics& kin, int leg, double t) const {
    const Eigen::Vector3d qt = q(kin, leg, t);
    ContactMeasurement c;
    c.foot = leg;
    c.p_body = kin.footPosition(leg, qt);
    c.cov = Eigen::Matrix3d::Identity() * 1e-6;
    c.v_body = kin.footJacobian(leg, qt) * qdot(kin, leg, t);
    return c;
  }
};

}  // namespace legkit::test
