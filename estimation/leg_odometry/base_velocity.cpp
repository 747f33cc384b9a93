#include "estimation/leg_odometry/base_velocity.hpp"

#include <Eigen/Dense>
#include <lie/so3.hpp>
#include <stdexcept>
#include <string>

#include "estimation/leg_odometry/checks.hpp"

namespace legkit::leg_odometry {

Eigen::Vector3d baseVelocityFromFoot(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                                     const Eigen::Vector3d& r, const Eigen::Vector3d& r_dot) {
  constexpr const char* who = "baseVelocityFromFoot";
  detail::checkRotation(R, who);
  detail::checkFinite(w_b, who, "body angular rate w_b");
  detail::checkFinite(r, who, "body-frame foot position r");
  detail::checkFinite(r_dot, who, "body-frame foot velocity r_dot");
  return -R * (w_b.cross(r) + r_dot);
}

Eigen::Vector3d baseVelocityFromFoot(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                                     const ContactMeasurement& contact) {
  if (!contact.v_body) {
    throw std::invalid_argument("baseVelocityFromFoot: the contact of foot " +
                                std::to_string(contact.foot) +
                                " carries no body-frame foot velocity (v_body)");
  }
  return baseVelocityFromFoot(R, w_b, contact.p_body, *contact.v_body);
}

Eigen::Matrix3d baseVelocityCovariance(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                                       const Eigen::Vector3d& r, const Eigen::Matrix3d& r_cov,
                                       const FootVelocityNoise& noise) {
  constexpr const char* who = "baseVelocityCovariance";
  detail::checkRotation(R, who);
  detail::checkFinite(w_b, who, "body angular rate w_b");
  detail::checkFinite(r, who, "body-frame foot position r");
  detail::checkCovariance(r_cov, who, "foot position covariance");
  detail::checkCovariance(noise.gyro_cov, who, "gyro covariance");
  detail::checkCovariance(noise.r_dot_cov, who, "foot velocity covariance");
  const Eigen::Matrix3d r_x = lie::hat3(r), w_x = lie::hat3(w_b);
  const Eigen::Matrix3d body =
      r_x * noise.gyro_cov * r_x.transpose() + w_x * r_cov * w_x.transpose() + noise.r_dot_cov;
  return R * body * R.transpose();
}

}  // namespace legkit::leg_odometry
