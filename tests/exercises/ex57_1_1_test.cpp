// Exercise 57.1.1: drift formulas checked against the kit's measured dead reckoning of a
// standing robot (readings from model/imu_model.hpp).
#include <catch2/catch.hpp>

#include "estimation/imu/drift_study.hpp"
#include "ex57_1_1.hpp"
#include "exercises/exercise_check.hpp"

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

TEST_CASE("57.1.1 (a) accelerometer bias 0.02 m/s^2: position after 30 s", "[ex57.1.1][hint 1]") {
  const auto kit = measured(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.0, 0.0));
  REQUIRE_REL(ex57_1_1::positionDriftFromAccelBias(0.02, 30.0), kit.position_error, 1e-6);
  REQUIRE_REL(ex57_1_1::positionDriftFromAccelBias(0.01, 60.0), 18.0, 1e-9);
}

TEST_CASE("57.1.1 (b) gyro bias 0.005 rad/s: attitude after 30 s in degrees",
          "[ex57.1.1][hint 2]") {
  const auto kit = measured(Eigen::Vector3d(0.0, 0.005, 0.0), Eigen::Vector3d::Zero());
  REQUIRE_REL(ex57_1_1::attitudeDriftDegFromGyroBias(0.005, 30.0), kit.attitude_error_deg, 1e-6);
  REQUIRE_NEAR(ex57_1_1::attitudeDriftDegFromGyroBias(0.01, 60.0), 34.38, 0.01);
}

TEST_CASE("57.1.1 (c) the gyro bias drags position through gravity", "[ex57.1.1][hint 2]") {
  const auto kit = measured(Eigen::Vector3d(0.0, 0.005, 0.0), Eigen::Vector3d::Zero());
  // small-angle formula vs the exact measured run: 0.15 rad of tilt, within 1 %
  REQUIRE_REL(ex57_1_1::positionDriftFromGyroBias(0.005, 30.0), kit.position_error, 0.01);
  REQUIRE_ABOVE(ex57_1_1::positionDriftFromGyroBias(0.005, 30.0),
                10.0 * ex57_1_1::positionDriftFromAccelBias(0.02, 30.0));
}
