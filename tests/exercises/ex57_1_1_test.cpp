// Exercise 57.1.1: drift formulas checked against the kit's measured dead reckoning of a
// standing robot (readings from model/imu_model.hpp).
#include <catch2/catch.hpp>

#include "estimation/imu/drift_study.hpp"
#include "ex57_1_1.hpp"

namespace {

legkit::imu::DriftSample measured(const Eigen::Vector3d& b_g, const Eigen::Vector3d& b_a) {
  legkit::imu::StationaryDriftStudy study;
  study.bias.b_g = b_g;
  study.bias.b_a = b_a;
  study.duration = 30.0;
  study.report_every = 30.0;
  return legkit::imu::driftAt(legkit::imu::runStationaryDrift(study), 30.0);
}

}  // namespace

TEST_CASE("57.1.1 (a) accelerometer bias 0.02 m/s^2: position after 30 s", "[ex57.1.1]") {
  const auto kit = measured(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.0, 0.0));
  CHECK(ex57_1_1::positionDriftFromAccelBias(0.02, 30.0) ==
        Approx(kit.position_error).epsilon(1e-6));
  CHECK(ex57_1_1::positionDriftFromAccelBias(0.01, 60.0) == Approx(18.0).epsilon(1e-9));
}

TEST_CASE("57.1.1 (b) gyro bias 0.005 rad/s: attitude after 30 s in degrees", "[ex57.1.1]") {
  const auto kit = measured(Eigen::Vector3d(0.0, 0.005, 0.0), Eigen::Vector3d::Zero());
  CHECK(ex57_1_1::attitudeDriftDegFromGyroBias(0.005, 30.0) ==
        Approx(kit.attitude_error_deg).epsilon(1e-6));
  CHECK(ex57_1_1::attitudeDriftDegFromGyroBias(0.01, 60.0) == Approx(34.38).margin(0.01));
}

TEST_CASE("57.1.1 (c) the gyro bias drags position through gravity", "[ex57.1.1]") {
  const auto kit = measured(Eigen::Vector3d(0.0, 0.005, 0.0), Eigen::Vector3d::Zero());
  // small-angle formula vs the exact measured run: 0.15 rad of tilt, within 1 %
  CHECK(ex57_1_1::positionDriftFromGyroBias(0.005, 30.0) ==
        Approx(kit.position_error).epsilon(0.01));
  CHECK(ex57_1_1::positionDriftFromGyroBias(0.005, 30.0) >
        10.0 * ex57_1_1::positionDriftFromAccelBias(0.02, 30.0));
}
