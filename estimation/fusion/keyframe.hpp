// One keyframe of the fixed-lag smoother (section 57.8), stored as the separate parameter blocks
// Ceres optimises. Each block is a plain array so that Ceres can point at it; the rotation is a
// 3x3 matrix in column-major order, moved on its manifold by lie::ceres::SO3Manifold
// (right plus: R <- R Exp(delta)); the other blocks are Euclidean.
#pragma once

#include <Eigen/Core>
#include <array>

namespace legkit::fusion {

struct Keyframe {
  double t = 0.0;                                      // [s]
  std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};  // R_WB, column-major
  std::array<double, 3> v{}, p{};                      // world velocity [m/s], position [m]
  std::array<double, 3> b_g{}, b_a{};                  // gyro [rad/s], accelerometer [m/s^2] bias
  std::array<double, 3> b_v{};  // leg-odometry velocity bias, body frame [m/s] (VILENS)

  Eigen::Map<Eigen::Matrix3d> Rmat() { return Eigen::Map<Eigen::Matrix3d>(R.data()); }
  Eigen::Map<const Eigen::Matrix3d> Rmat() const {
    return Eigen::Map<const Eigen::Matrix3d>(R.data());
  }
};

}  // namespace legkit::fusion
