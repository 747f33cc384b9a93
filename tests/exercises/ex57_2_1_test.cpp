// Exercise 57.2.1: step-by-step gyro integration of a pure bias, against the kit's
// legkit::imu::gyroStep and lie::SO3d.
#include <catch2/catch.hpp>
#include <random>

#include "estimation/imu/gyro_integration.hpp"
#include "ex57_2_1.hpp"
#include "exercises/exercise_check.hpp"

TEST_CASE("57.2.1 rodriguesStep equals R Exp(w dt)", "[ex57.2.1][hint 1]") {
  std::mt19937 gen(5);
  std::normal_distribution<double> n(0.0, 2.0);
  for (int i = 0; i < 50; ++i) {
    const lie::SO3d R = lie::SO3d::Random(gen);
    const Eigen::Vector3d w(n(gen), n(gen), n(gen));
    for (double dt : {1e-9, 1e-3, 0.5}) {
      const Eigen::Matrix3d expected = (R * lie::SO3d::Exp(w * dt)).matrix();
      REQUIRE_NEAR(ex57_2_1::rodriguesStep(R.matrix(), w, dt), expected, 1e-13);
    }
  }
  REQUIRE_THROWS_AS(
      ex57_2_1::rodriguesStep(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 0.0),
      std::invalid_argument);
}

TEST_CASE("57.2.1 the chapter's bias over 100 steps of 1 ms", "[ex57.2.1][hint 2]") {
  const Eigen::Vector3d b_g(0.01, 0.005, -0.008);
  const Eigen::Vector3d err = ex57_2_1::attitudeErrorFromBias(b_g, 1e-3, 100);
  lie::SO3d R;
  for (int k = 0; k < 100; ++k) R = legkit::imu::gyroStep(R, b_g, Eigen::Vector3d::Zero(), 1e-3);
  REQUIRE_NEAR(err, R.Log(), 1e-15);
  // (0.001, 0.0005, -0.0008) rad: 1.375 mrad, 0.0788 deg, about the bias axis
  REQUIRE_REL(err.norm(), b_g.norm() * 0.1, 1e-12);
  REQUIRE_REL(err.norm() * 180.0 / M_PI, 0.07878, 1e-3);
  // After a minute (60000 steps) the error is still b_g t, one axis throughout: 0.825 rad, 47.3 deg
  const Eigen::Vector3d minute = ex57_2_1::attitudeErrorFromBias(b_g, 1e-3, 60000);
  REQUIRE_NEAR(minute, b_g * 60.0, 1e-9);
  REQUIRE_REL(minute.norm() * 180.0 / M_PI, 47.26, 1e-3);
}

TEST_CASE("57.2.1 random biases and step counts match the kit", "[ex57.2.1][hint 3]") {
  std::mt19937 gen(9);
  std::normal_distribution<double> n(0.0, 0.05);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d b_g(n(gen), n(gen), n(gen));
    const int steps = 10 + 50 * i;
    lie::SO3d R;
    for (int k = 0; k < steps; ++k)
      R = legkit::imu::gyroStep(R, b_g, Eigen::Vector3d::Zero(), 2e-3);
    REQUIRE_NEAR(ex57_2_1::attitudeErrorFromBias(b_g, 2e-3, steps), R.Log(), 1e-12);
  }
}
