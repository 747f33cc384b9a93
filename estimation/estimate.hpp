// The base state an estimator reports: attitude, velocity and position at time t.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace legkit {

struct EstimateSample {
  double t = 0.0;                                         // [s]
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // R: body to world
  Eigen::Vector3d v = Eigen::Vector3d::Zero();            // world velocity [m/s]
  Eigen::Vector3d p = Eigen::Vector3d::Zero();            // world position [m]
};

}  // namespace legkit
