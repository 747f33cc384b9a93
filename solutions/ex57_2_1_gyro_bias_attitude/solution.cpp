// Reference solution to exercise 57.2.1.
#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "ex57_2_1.hpp"

namespace ex57_2_1 {

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
  return S;
}

}  // namespace

// Exp(phi) = I + sin(theta)/theta [phi]_x + (1 - cos(theta))/theta^2 [phi]_x^2, theta = |phi|;
// below theta ~ 1e-4 the coefficients' Taylor series (1 - theta^2/6, 1/2 - theta^2/24) are exact
// to double precision and avoid the 0/0.
Eigen::Matrix3d rodriguesStep(const Eigen::Matrix3d& R, const Eigen::Vector3d& w, double dt) {
  if (!(dt > 0.0)) throw std::invalid_argument("rodriguesStep: dt must be positive");
  const Eigen::Vector3d phi = w * dt;
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const double a = t < 1e-4 ? 1.0 - t2 / 6.0 : std::sin(t) / t;
  const double b = t < 1e-4 ? 0.5 - t2 / 24.0 : (1.0 - std::cos(t)) / t2;
  const Eigen::Matrix3d P = skew(phi);
  return R * (Eigen::Matrix3d::Identity() + a * P + b * P * P);
}

// With zero true rate the integrated attitude is itself the error. The rotation vector comes
// from Eigen's angle-axis (through the quaternion, accurate for small angles).
Eigen::Vector3d attitudeErrorFromBias(const Eigen::Vector3d& b_g, double dt, int steps) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  for (int k = 0; k < steps; ++k) R = rodriguesStep(R, b_g, dt);
  const Eigen::AngleAxisd aa(Eigen::Quaterniond(R).normalized());
  return aa.angle() * aa.axis();
}

}  // namespace ex57_2_1
