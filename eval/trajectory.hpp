// What an estimator reports at each log row, and the per-row errors against ground truth.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace legkit::eval {

// The base state an estimator reports at time t (world frame, R body to world).
struct EstimateSample {
  double t = 0.0;
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
};

using Trajectory = std::vector<EstimateSample>;

}  // namespace legkit::eval
