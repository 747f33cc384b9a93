// Exercise 57.9.2: which estimator for three scenarios, and the runs behind the choice.
#pragma once

#include <string>

#include "io/log.hpp"

namespace ex57_9_2 {

// The chapter's three scenarios.
enum class Scenario {
  kFactoryPatrol,     // (a) a quadruped patrolling a flat factory floor, proprioception only
  kMineExploration,   // (b) a quadruped exploring a mine over 1 km and more, with a LiDAR
  kHumanoidBuilding,  // (c) a humanoid on a building site that must place its hand precisely
};

// The families of section 57.9's selection guide.
enum class Choice {
  kLinearKf,         // attitude from the IMU, linear KF on [p, v, feet] (57.4)
  kInvariantEkf,     // proprioceptive InEKF with attitude in the state (57.5)
  kModularLidarEkf,  // a modular EKF with loosely coupled LiDAR corrections (Pronto, 57.8)
  kFactorGraph,      // a tightly coupled visual/LiDAR/inertial/leg factor graph (VILENS, 57.8)
};

Choice choose(Scenario scenario);

// What a proprioceptive estimator drifts by over a log with ground truth.
struct Drift {
  double distance = 0.0;        // the truth's path length, sum of |p_{k+1} - p_k| [m]
  double position_error = 0.0;  // |p_hat - p| at the last row [m]
  double yaw_error_deg = 0.0;   // |yaw_hat - yaw| at the last row, wrapped to [0, 180] [deg]
};

// Runs the kit's estimator `estimator` (a name of legkit::makeEstimator) over the log from the
// truth at row 0 (eval::initialState), its stance from the log's contact flags through a
// LogFrontend on the analytic Go2 (model::QuadrupedKinematics, default front-end noise), and
// measures its drift (eval::yawError for the yaw). Throws std::invalid_argument for a log without
// ground truth or a run that fails.
Drift drift(const legkit::io::Log& log, const std::string& estimator);

}  // namespace ex57_9_2
