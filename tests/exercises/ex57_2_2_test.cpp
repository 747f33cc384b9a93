// Exercise 57.2.2: gravity says nothing about yaw (a zero Jacobian column); a magnetometer does,
// in proportion to the horizontal field. Checked against model/imu_model.hpp and finite
// differences.
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "ex57_2_2.hpp"
#include "exercises/exercise_check.hpp"
#include "model/imu_model.hpp"

namespace {

const Eigen::Vector3d kEarthField(20.0, 0.0, -45.0);  // [uT], a mid-latitude field, north = x

Eigen::Vector3d randomRpy(std::mt19937& gen) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return Eigen::Vector3d(3.0 * u(gen), 1.3 * u(gen), 3.0 * u(gen));  // |pitch| < 75 deg
}

}  // namespace

TEST_CASE("57.2.2 the accelerometer at rest reads R^T (-g), as the kit's sensor model",
          "[ex57.2.2][hint 1]") {
  std::mt19937 gen(1);
  for (int i = 0; i < 30; ++i) {
    const Eigen::Vector3d rpy = randomRpy(gen);
    const Eigen::Matrix3d R = ex57_2_2::rotationFromRpy(rpy);
    REQUIRE_NEAR(R.transpose() * R, Eigen::Matrix3d::Identity(), 1e-12);
    REQUIRE_NEAR(R.determinant(), 1.0, 1e-12);
    const Eigen::Vector3d kit =
        legkit::model::idealReading(R, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), {}).a_m;
    REQUIRE_NEAR(ex57_2_2::accelerometerAtRest(rpy), kit, 1e-12);
    REQUIRE_NEAR(ex57_2_2::magnetometer(rpy, kEarthField), R.transpose() * kEarthField, 1e-12);
  }
  // the yaw convention: R(0, 0, psi) turns the body x axis towards world y
  const Eigen::Matrix3d Rz = ex57_2_2::rotationFromRpy(Eigen::Vector3d(0.0, 0.0, 0.3));
  REQUIRE_NEAR(Rz * Eigen::Vector3d::UnitX(), Eigen::Vector3d(std::cos(0.3), std::sin(0.3), 0),
               1e-12);
}

TEST_CASE("57.2.2 gravity's Jacobian has a zero yaw column and full roll/pitch rank",
          "[ex57.2.2][hint 2]") {
  std::mt19937 gen(2);
  const double h = 1e-6;
  for (int i = 0; i < 30; ++i) {
    const Eigen::Vector3d rpy = randomRpy(gen);
    const Eigen::Matrix3d J = ex57_2_2::measurementJacobian(0, rpy, kEarthField);
    for (int j = 0; j < 3; ++j) {
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e(j) = h;
      const Eigen::Vector3d fd =
          (ex57_2_2::accelerometerAtRest(rpy + e) - ex57_2_2::accelerometerAtRest(rpy - e)) /
          (2 * h);
      REQUIRE_NEAR(J.col(j), fd, 1e-6);
    }
    REQUIRE_NEAR(J.col(2), Eigen::Vector3d::Zero(), 1e-12);  // yaw is invisible to gravity
    // roll and pitch are seen: |J_roll x J_pitch| = g^2 cos(pitch)
    REQUIRE_REL(J.col(0).cross(J.col(1)).norm(), 9.81 * 9.81 * std::cos(rpy(1)), 1e-9);
  }
}

TEST_CASE("57.2.2 the magnetometer sees yaw in proportion to the horizontal field",
          "[ex57.2.2][hint 2]") {
  std::mt19937 gen(3);
  const Eigen::Vector3d vertical(0.0, 0.0, -60.0);  // at a magnetic pole
  for (int i = 0; i < 30; ++i) {
    const Eigen::Vector3d rpy = randomRpy(gen);
    const Eigen::Matrix3d J = ex57_2_2::measurementJacobian(1, rpy, kEarthField);
    REQUIRE_REL(J.col(2).norm(), 20.0, 1e-12);  // |m_horizontal|
    REQUIRE_NEAR(ex57_2_2::measurementJacobian(1, rpy, vertical).col(2), Eigen::Vector3d::Zero(),
                 1e-12);
  }
}

TEST_CASE("57.2.2 a nearby steel disturbance turns into a heading error", "[ex57.2.2][hint 3]") {
  // 10 uT sideways against 20 uT of horizontal field: atan(1/2) = 26.6 deg
  REQUIRE_REL(ex57_2_2::headingErrorFromDisturbance(kEarthField, Eigen::Vector3d(0.0, 10.0, 0.0)),
              std::atan(0.5), 1e-12);
  // a purely vertical disturbance does not change the heading
  REQUIRE_BELOW(ex57_2_2::headingErrorFromDisturbance(kEarthField, Eigen::Vector3d(0.0, 0.0, 30.0)),
                1e-12);
  // the same disturbance hurts more where the horizontal field is weak (5 uT): 63.4 deg
  REQUIRE_REL(ex57_2_2::headingErrorFromDisturbance(Eigen::Vector3d(5.0, 0.0, -58.0),
                                                    Eigen::Vector3d(0.0, 10.0, 0.0)),
              std::atan(2.0), 1e-12);
}
