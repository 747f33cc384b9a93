// The closed-loop interface of the physics simulator (sim/physics_simulator.hpp): where the walking
// controller gets its base state from when it does not use the truth (exercise 57.X: what a wrong
// estimate does to the controller).
#pragma once

#include <Eigen/Core>

#include "io/log.hpp"

namespace legkit::sim {

// What a closed-loop controller uses instead of the truth (world frame).
struct BaseEstimate {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
};

// A source of base estimates fed with every log row as it is made (e.g. an estimator).
class BaseStateSource {
 public:
  virtual ~BaseStateSource() = default;
  // False: no estimate yet (the controller keeps using the truth).
  virtual bool update(const io::LogRow& row, BaseEstimate& out) = 0;
};

}  // namespace legkit::sim
