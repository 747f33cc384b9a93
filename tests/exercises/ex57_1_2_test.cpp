// Exercise 57.1.2: the number behind the discussion, the IMU-only drift over one gap between
// corrections, checked against the kit's dead reckoning.
#include <catch2/catch.hpp>

#include "estimation/imu/drift_study.hpp"
#include "ex57_1_2.hpp"
#include "exercises/exercise_check.hpp"

TEST_CASE("57.1.2 drift over one camera gap matches the kit's dead reckoning",
          "[ex57.1.2][hint 2]") {
  legkit::imu::StationaryDriftStudy study;
  study.bias.b_a = Eigen::Vector3d(0.0, 0.01, 0.0);
  study.dt = 1.0 / 3000.0;  // a 3 kHz IMU, so that 1/30 s is a whole number of samples
  study.duration = 1.0 / 30.0;
  study.report_every = study.duration;
  const auto kit = legkit::imu::driftAt(legkit::imu::runStationaryDrift(study), study.duration);
  REQUIRE_REL(ex57_1_2::driftOverGap(0.01, 1.0 / 30.0), kit.position_error, 1e-6);
  REQUIRE_REL(ex57_1_2::driftOverGap(0.01, 1e-3), 5e-9, 1e-9);
}

TEST_CASE("57.1.2 per-gap drift is about 1111 times larger at 30 Hz than at 1 kHz",
          "[ex57.1.2][hint 3]") {
  REQUIRE_REL(ex57_1_2::gapDriftRatio(30.0, 1000.0), 1000.0 * 1000.0 / 900.0, 1e-12);
  REQUIRE_REL(ex57_1_2::gapDriftRatio(30.0, 1000.0),
              ex57_1_2::driftOverGap(0.01, 1.0 / 30.0) / ex57_1_2::driftOverGap(0.01, 1e-3), 1e-12);
}
