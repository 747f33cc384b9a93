// Reader for the text log of the reference contact-aided InEKF (RossHartley/invariant-ekf,
// src/data/imu_kinematic_measurements.txt: a Cassie biped), so that the kit's filter can be run on
// the same real data as the reference.
//
// Format: one record per line, fields separated by spaces:
//   IMU t wx wy wz ax ay az                  gyro [rad/s] and accelerometer [m/s^2], IMU frame
//   CONTACT t id c [id c ...]                contact indicator c (0 or 1) per foot id
//   KINEMATIC t [id qw qx qy qz px py pz C_00 .. C_55] ...   per foot: its pose in the IMU frame
//                                            and the 6 x 6 covariance of that pose (row-major,
//                                            rotation block first)
// Every timestamp has one line of each kind, IMU first. Only the foot positions and the position
// block of their covariance are kept: the kit's contact measurement is a point.
// Any malformed line throws io::LogError naming the file, the line and what was expected.
#pragma once

#include <Eigen/Core>
#include <array>
#include <istream>
#include <string>
#include <vector>

#include "model/contact_measurement.hpp"
#include "model/imu_model.hpp"

namespace legkit::io {

constexpr int kHartleyMaxFeet = 4;  // foot ids 0..3 (Cassie uses 0 = left, 1 = right)

struct HartleySample {
  double t = 0.0;         // [s]
  model::ImuReading imu;  // gyro and accelerometer, IMU frame
  // The feet listed by the KINEMATIC line, in file order, with their contact indicator.
  std::array<ContactMeasurement, kHartleyMaxFeet> feet{};
  std::array<bool, kHartleyMaxFeet> contact{};
  int num_feet = 0;
  int line = 0;  // 1-based line of the IMU record
};

struct HartleyLog {
  std::string file;
  std::vector<HartleySample> samples;
};

// The feet of a sample whose contact indicator is 1 (the stance feet), written to `out`; returns
// how many. A foot marked in contact without a KINEMATIC entry has nothing to measure and is left
// out, as the reference does.
int stanceFeet(const HartleySample& sample, std::array<ContactMeasurement, kHartleyMaxFeet>& out);

HartleyLog readHartleyLog(const std::string& path);
// The same from a stream; `name` is used in error messages.
HartleyLog parseHartleyLog(std::istream& in, const std::string& name);

}  // namespace legkit::io
