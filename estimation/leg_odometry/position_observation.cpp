#include "estimation/leg_odometry/position_observation.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <lie/so3.hpp>
#include <stdexcept>

#include "estimation/leg_odometry/checks.hpp"

namespace legkit::leg_odometry {
namespace {

void checkFootRadius(double rho, const char* who) {
  if (!std::isfinite(rho) || rho < 0.0) {
    throw std::invalid_argument(std::string(who) + ": foot radius must be finite and >= 0");
  }
}

}  // namespace

Eigen::Vector3d basePositionFromFoot(const Eigen::Vector3d& d, const Eigen::Matrix3d& R,
                                     const Eigen::Vector3d& r) {
  constexpr const char* who = "basePositionFromFoot";
  detail::checkRotation(R, who);
  detail::checkFinite(d, who, "world foot position d");
  detail::checkFinite(r, who, "body-frame foot position r");
  return d - R * r;
}

Eigen::Vector3d footWorldPosition(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                                  const Eigen::Vector3d& r) {
  constexpr const char* who = "footWorldPosition";
  detail::checkRotation(R, who);
  detail::checkFinite(p, who, "base position p");
  detail::checkFinite(r, who, "body-frame foot position r");
  return p + R * r;
}

double footContactHeight(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                         const Eigen::Vector3d& r, double foot_radius) {
  checkFootRadius(foot_radius, "footContactHeight");
  return footWorldPosition(p, R, r).z() - foot_radius;
}

double baseHeightFromFoot(double ground_height, const Eigen::Matrix3d& R, const Eigen::Vector3d& r,
                          double foot_radius) {
  constexpr const char* who = "baseHeightFromFoot";
  checkFootRadius(foot_radius, who);
  if (!std::isfinite(ground_height)) {
    throw std::invalid_argument(std::string(who) + ": ground height is not finite");
  }
  detail::checkRotation(R, who);
  detail::checkFinite(r, who, "body-frame foot position r");
  return ground_height + foot_radius - (R * r).z();
}

Eigen::Vector3d footMeasurement(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                                const Eigen::Vector3d& d, Eigen::Matrix3d* J_y_p,
                                Eigen::Matrix3d* J_y_theta, Eigen::Matrix3d* J_y_d) {
  constexpr const char* who = "footMeasurement";
  detail::checkRotation(R, who);
  detail::checkFinite(p, who, "base position p");
  detail::checkFinite(d, who, "world foot position d");
  const Eigen::Matrix3d Rt = R.transpose();
  // R^T = R_hat^T Exp(-dtheta) = R_hat^T (I - [dtheta]_x) to first order, and
  // -[dtheta]_x a = [a]_x dtheta, which gives the attitude column R^T [d - p]_x.
  if (J_y_p) *J_y_p = -Rt;
  if (J_y_theta) *J_y_theta = Rt * lie::hat3(Eigen::Vector3d(d - p));
  if (J_y_d) *J_y_d = Rt;
  return Rt * (d - p);
}

}  // namespace legkit::leg_odometry
