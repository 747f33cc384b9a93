// Small helpers shared by the simulator tests.
#pragma once

#include <Eigen/Core>
#include <string>

#include "model/quadruped.hpp"
#include "sim/simulator.hpp"

namespace legkit::sim::test {

// A short, noise-free run of a scenario (readings are the exact kinematic quantities).
inline SimOptions noiselessRun(const std::string& scenario, double duration) {
  SimOptions o;
  o.scenario = scenarioByName(scenario);
  o.duration = duration;
  o.noiseless();
  return o;
}

// Joint angles of one leg from a log row.
inline Eigen::Vector3d legAngles(const io::LogRow& row, int leg) {
  return row.q.segment<3>(io::kJointsPerLeg * leg);
}
inline Eigen::Vector3d legRates(const io::LogRow& row, int leg) {
  return row.dq.segment<3>(io::kJointsPerLeg * leg);
}

// The foot's world position as an estimator would reconstruct it: p + R FK(q).
inline Eigen::Vector3d footInWorld(const model::QuadrupedKinematics& kin, const io::LogRow& row,
                                   int leg) {
  return row.gt_p + row.gt_q.toRotationMatrix() * kin.footPosition(leg, legAngles(row, leg));
}

}  // namespace legkit::sim::test
