// Input checks shared by the leg-odometry functions: each throws std::invalid_argument naming the
// function and the offending input. Internal to this module.
#pragma once

#include <Eigen/Core>
#include <stdexcept>
#include <string>

namespace legkit::leg_odometry::detail {

inline void checkFinite(const Eigen::Ref<const Eigen::MatrixXd>& x, const char* who,
                        const char* what) {
  if (!x.allFinite())
    throw std::invalid_argument(std::string(who) + ": " + what + " is not finite");
}

// R must be finite, orthonormal and proper to 1e-6 (an estimate renormalised now and then).
inline void checkRotation(const Eigen::Matrix3d& R, const char* who) {
  checkFinite(R, who, "attitude R");
  const double orthonormality = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  if (orthonormality > 1e-6 || R.determinant() < 0.0) {
    throw std::invalid_argument(std::string(who) + ": attitude R is not a rotation matrix");
  }
}

// Finite and symmetric to 1e-9 relative (positive semi-definiteness is the caller's promise).
inline void checkCovariance(const Eigen::Matrix3d& C, const char* who, const char* what) {
  checkFinite(C, who, what);
  if ((C - C.transpose()).norm() > 1e-9 * (1.0 + C.norm())) {
    throw std::invalid_argument(std::string(who) + ": " + what + " is not symmetric");
  }
}

}  // namespace legkit::leg_odometry::detail
