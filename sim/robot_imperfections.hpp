// What a real robot has and the kit's ideal simulated one does not (issue: real robots read their
// legs short and lose yaw while turning). Each is off (0) by default; the physics-real scenario
// (sim/physics_scenario.hpp) turns every one on with the physical value given beside it.
//
//   link_length_error   the simulated thigh and calf are (1 + e) times the model's lengths, which
//                       the estimators keep (QuadrupedGeometry::go2()): the legs read every stance
//                       displacement short by about e
//   joint_offset_sigma  each joint's zero is off by a constant N(0, sigma^2) drawn once per run
//                       (random stream 6): an encoder calibrated by eye
//   backlash            gear play: the reading follows the joint only once it has moved half the
//                       play past the last reading (a play operator of width `backlash`)
//   encoder_resolution  readings are whole multiples of this step (a quantising encoder)
//   encoder_delay       the encoders report the joints as they were this long ago (rounded to
//                       whole log rows): a time offset between the IMU and the encoders
//   imu_rate            the IMU is sampled at this rate and each reading held over the log rows
//                       until the next (0: every row is a fresh sample)
//   foot_timeconst      compliant feet: the time constant of the foot spheres' contacts (MuJoCo's
//                       solref; 0: MuJoCo's 0.02 s): a longer one lets a loaded foot sink deeper
//                       and roll as the load moves
#pragma once

namespace legkit::sim {

struct RobotImperfections {
  double link_length_error = 0.0;   // [-], |e| <= 0.1
  double joint_offset_sigma = 0.0;  // [rad]
  double backlash = 0.0;            // [rad]
  double encoder_resolution = 0.0;  // [rad]
  double encoder_delay = 0.0;       // [s]
  double imu_rate = 0.0;            // [Hz], 0 or in (0, log rate]
  double foot_timeconst = 0.0;      // [s], 0 or in [0.002, 0.2]
};

}  // namespace legkit::sim
