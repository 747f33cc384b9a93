// The navigation state an IMU integrates: attitude R (body to world), world velocity v and
// world position p.
#pragma once

#include <Eigen/Core>

#include "lie/so3.hpp"

namespace legkit::imu {

struct NavState {
  lie::SO3d R;
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
};

}  // namespace legkit::imu
