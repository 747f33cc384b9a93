// Exercise 57.7.2: every foot slipping at once (a robot pushed on ice): what the legs say, what the
// IMU says, and what the feet say about each other.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "io/log.hpp"
#include "model/quadruped.hpp"

namespace ex57_7_2 {

// One row of the comparison, from the anchor on.
struct Comparison {
  double t = 0.0;  // [s]
  // The legs' common velocity: the mean over the feet whose contact flag is set of
  // v_i = -R (w x r_i + J_i dq_i) (section 57.3), R the row's true attitude gt_q, w the gyro
  // reading, r_i = FK(q_i) [m/s, world]. Zero when no foot is in contact.
  Eigen::Vector3d v_legs = Eigen::Vector3d::Zero();
  // The IMU alone from the anchor: v_imu = gt_v at the anchor row, then from row k to row k + 1
  // v_imu += (R_k a_m,k + g) (t_{k+1} - t_k) with g = model::gravity() [m/s, world].
  Eigen::Vector3d v_imu = Eigen::Vector3d::Zero();
  // The feet's disagreement: the largest |v_i - v_j| over pairs of feet in contact (0 with fewer
  // than two) [m/s].
  double spread = 0.0;
};

// One entry per row with t >= t_anchor (the first one is the anchor row). Throws
// std::invalid_argument when the log lacks joints, contact flags or ground truth, or no row is at
// or after t_anchor.
std::vector<Comparison> legsVersusImu(const legkit::io::Log& log, double t_anchor,
                                      const legkit::model::QuadrupedKinematics& kin);

}  // namespace ex57_7_2
