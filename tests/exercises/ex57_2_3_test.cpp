// Exercise 57.2.3: one-step discretisation error of the Rodrigues gyro step, against the kit's
// legkit::imu::gyroStepError.
#include <catch2/catch.hpp>
#include <cmath>

#include "estimation/imu/gyro_integration.hpp"
#include "ex57_2_3.hpp"
#include "exercises/exercise_check.hpp"

using legkit::imu::RateSample;

namespace {

// The kit's landing ramp (+5 rad/s per ms on y, 2 rad/s of roll) and a 100 Hz impact ringing.
Eigen::Vector3d impact(double t) {
  return Eigen::Vector3d(2.0, 5000.0 * t, 0.0);
}
Eigen::Vector3d ringing(double t) {
  return Eigen::Vector3d(1.0, 0.0, 0.0) +
         6.0 * std::sin(2.0 * M_PI * 100.0 * t) * Eigen::Vector3d(0.0, 1.0, 1.0);
}

}  // namespace

TEST_CASE("57.2.3 one-step error matches the kit for an impact and a ringing",
          "[ex57.2.3][hint 2]") {
  for (double dt : {5e-4, 1e-3, 2.5e-3}) {
    REQUIRE_REL(ex57_2_3::oneStepError(impact, dt),
                legkit::imu::gyroStepError(impact, 0.0, dt, RateSample::kStart), 1e-3);
    REQUIRE_REL(ex57_2_3::oneStepError(ringing, dt),
                legkit::imu::gyroStepError(ringing, 0.0, dt, RateSample::kStart), 1e-3);
  }
  // the numbers quoted in answer.md: 2.5 mrad at 1 kHz, 15.6 mrad at 400 Hz
  REQUIRE_REL(ex57_2_3::oneStepError(impact, 1e-3), 2.5e-3, 1e-3);
  REQUIRE_REL(ex57_2_3::oneStepError(impact, 2.5e-3), 1.5625e-2, 1e-3);
}

TEST_CASE("57.2.3 a constant rate has no discretisation error", "[ex57.2.3][hint 1]") {
  const auto constant = [](double) { return Eigen::Vector3d(0.3, -2.0, 1.0); };
  REQUIRE_BELOW(ex57_2_3::oneStepError(constant, 5e-3), 1e-12);
}

TEST_CASE("57.2.3 the derived leading term predicts the ramp error", "[ex57.2.3][hint 3]") {
  const Eigen::Vector3d w0(2.0, 0.0, 0.0), alpha(0.0, 5000.0, 0.0);
  const auto ramp = [&](double t) { return Eigen::Vector3d(w0 + alpha * t); };
  for (double dt : {2.5e-4, 1e-3}) {
    const double kit = legkit::imu::gyroStepError(ramp, 0.0, dt, RateSample::kStart);
    REQUIRE_REL(ex57_2_3::predictedRampError(w0, alpha, dt), kit, 1e-3);
  }
}

TEST_CASE("57.2.3 the step a landing impact needs for a 0.1 mrad error", "[ex57.2.3][hint 3]") {
  const double dt = ex57_2_3::maxStepForTolerance(5000.0, 1e-4);
  REQUIRE_REL(dt, 2e-4, 1e-9);  // 5 kHz
  const auto ramp = [](double t) { return Eigen::Vector3d(0.0, 5000.0 * t, 0.0); };
  REQUIRE_REL(legkit::imu::gyroStepError(ramp, 0.0, dt, RateSample::kStart), 1e-4, 1e-3);
}
