// The analytic base motion of a scenario: position, velocity and acceleration in the world,
// attitude and body angular rate, all exact at any instant (sim/jet.hpp carries the derivatives).
//
// Attitude is R = Rz(yaw) Ry(pitch) Rx(roll) (body to world), with the body rate
//   w = (roll' - yaw' sin(pitch),
//        pitch' cos(roll) + yaw' sin(roll) cos(pitch),
//        yaw' cos(roll) cos(pitch) - pitch' sin(roll))        (body frame).
#pragma once

#include <Eigen/Core>

#include "sim/scenario.hpp"

namespace legkit::sim {

struct BaseState {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();      // position, world [m]
  Eigen::Vector3d v = Eigen::Vector3d::Zero();      // velocity, world [m/s]
  Eigen::Vector3d a = Eigen::Vector3d::Zero();      // acceleration, world [m/s^2]
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // attitude, body to world
  Eigen::Vector3d w = Eigen::Vector3d::Zero();      // angular rate, body frame [rad/s]
  double yaw = 0.0;                                 // heading [rad]
};

class BaseTrajectory {
 public:
  explicit BaseTrajectory(const Scenario& scenario) : s_(scenario) {}
  BaseState at(double t) const;

 private:
  Scenario s_;
};

}  // namespace legkit::sim
