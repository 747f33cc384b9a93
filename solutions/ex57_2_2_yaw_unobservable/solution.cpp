// Reference solution to exercise 57.2.2.
#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "ex57_2_2.hpp"

namespace ex57_2_2 {

Eigen::Matrix3d rotationFromRpy(const Eigen::Vector3d& rpy) {
  using Eigen::AngleAxisd;
  return (AngleAxisd(rpy(2), Eigen::Vector3d::UnitZ()) *
          AngleAxisd(rpy(1), Eigen::Vector3d::UnitY()) *
          AngleAxisd(rpy(0), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d accelerometerAtRest(const Eigen::Vector3d& rpy) {
  return rotationFromRpy(rpy).transpose() * Eigen::Vector3d(0.0, 0.0, 9.81);  // R^T (0 - g)
}

Eigen::Vector3d magnetometer(const Eigen::Vector3d& rpy, const Eigen::Vector3d& m_world) {
  return rotationFromRpy(rpy).transpose() * m_world;
}

// Analytic: R = Rz Ry Rx, so R^T = Rx^T Ry^T Rz^T and each angle's derivative replaces its
// factor by (d/dangle of the factor). For a world vector u along z (gravity), Rz^T u = u does
// not depend on yaw, so the yaw column vanishes identically.
Eigen::Matrix3d measurementJacobian(int which, const Eigen::Vector3d& rpy,
                                    const Eigen::Vector3d& m_world) {
  if (which != 0 && which != 1) throw std::invalid_argument("measurementJacobian: which is 0 or 1");
  const Eigen::Vector3d u = which == 0 ? Eigen::Vector3d(0.0, 0.0, 9.81) : m_world;
  const auto rot = [](int axis, double a) {
    return Eigen::AngleAxisd(a, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
  };
  const auto hat = [](const Eigen::Vector3d& v) {
    Eigen::Matrix3d S;
    S << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
    return S;
  };
  // d(Rot(e, a)^T)/da = -[e]_x Rot(e, a)^T
  const Eigen::Matrix3d Rxt = rot(0, rpy(0)).transpose(), Ryt = rot(1, rpy(1)).transpose(),
                        Rzt = rot(2, rpy(2)).transpose();
  Eigen::Matrix3d J;
  J.col(0) = -hat(Eigen::Vector3d::UnitX()) * Rxt * Ryt * Rzt * u;
  J.col(1) = Rxt * (-hat(Eigen::Vector3d::UnitY()) * Ryt) * Rzt * u;
  J.col(2) = Rxt * Ryt * (-hat(Eigen::Vector3d::UnitZ()) * Rzt) * u;
  return J;
}

double headingErrorFromDisturbance(const Eigen::Vector3d& m_world,
                                   const Eigen::Vector3d& disturbance) {
  const Eigen::Vector3d measured = m_world + disturbance;
  const double a = std::atan2(m_world(1), m_world(0));
  const double b = std::atan2(measured(1), measured(0));
  return std::abs(std::remainder(b - a, 2.0 * M_PI));
}

}  // namespace ex57_2_2
