// Faults the simulator can inject, so that detectors and estimators can be tested against a
// known truth. All are off by default.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace legkit::sim {

// A stance foot sliding on the ground: between `start` and `start + duration`, whenever leg
// `leg` is in stance, its foot moves in the world at `speed` along `direction` (horizontal,
// normalised by the simulator). The contact flag stays 1: the robot does not know.
struct SlipFault {
  int leg = -1;                                          // -1: no slip; 0..3: FL, FR, RL, RR
  double start = 0.0;                                    // [s]
  double duration = 0.0;                                 // [s]
  double speed = 0.0;                                    // [m/s]
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // world frame
};

// A time window [start, start + duration) in which no IMU sample (no log row) is recorded.
struct Dropout {
  double start = 0.0;     // [s]
  double duration = 0.0;  // [s]
};

struct Faults {
  SlipFault slip;
  // The logged contact flags lag the true contacts by this much [s] (negative: they lead):
  // flag(t) = true_contact(t - contact_offset). Forces and torques stay on the true timing.
  double contact_offset = 0.0;
  std::vector<Dropout> dropouts;     // rows removed in these windows
  double dropout_probability = 0.0;  // besides, each row is dropped with this probability
};

}  // namespace legkit::sim
