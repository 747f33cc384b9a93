// Exercise 57.4.2: the linear KF's noise settings and the bias-variance trade-off they set.
#include <catch2/catch.hpp>
#include <cmath>

#include "eval/monte_carlo.hpp"
#include "eval/runner.hpp"
#include "ex57_4_2.hpp"
#include "exercises/exercise_check.hpp"
#include "sim/simulator.hpp"

using namespace legkit;
using ex57_4_2::Scales;

namespace {

sim::SimOptions trot() {
  sim::SimOptions options;
  options.scenario = sim::scenarioByName("trot");
  options.duration = 10.0;
  options.seed = 4;
  return options;
}

// One simulated trot, shared by the test cases (simulating it is the slow part).
const io::Log& trotLog() {
  static const io::Log log = sim::simulate(trot()).log;
  return log;
}

const FrontendNoise kMatched = eval::matchedFrontendNoise(trot());
constexpr double kWindow = 1.0;  // [s]

}  // namespace

TEST_CASE("ex57.4.2: filterParams scales each variance by its own factor", "[ex57.4.2][hint 1]") {
  linear_kf::LinearKfParams nominal;
  nominal.foot_swing_density = 7.0;
  nominal.sigma_position = 0.02;
  const auto p = ex57_4_2::filterParams({100.0, 4.0, 9.0}, nominal);
  REQUIRE_REL(p.foot_stance_density, 10.0 * nominal.foot_stance_density, 1e-12);
  REQUIRE_REL(p.imu.accel_noise_density, 2.0 * nominal.imu.accel_noise_density, 1e-12);
  REQUIRE_REL(p.foot_velocity_sigma, 3.0 * nominal.foot_velocity_sigma, 1e-12);
  // Everything else is the nominal's.
  REQUIRE(p.foot_swing_density == 7.0);
  REQUIRE(p.sigma_position == 0.02);
  REQUIRE(p.imu.gyro_noise_density == nominal.imu.gyro_noise_density);
  REQUIRE(p.imu.accel_bias_random_walk == nominal.imu.accel_bias_random_walk);
  REQUIRE(p.attitude.sigma_tilt == nominal.attitude.sigma_tilt);

  const auto same = ex57_4_2::filterParams({}, nominal);
  REQUIRE(same.foot_stance_density == nominal.foot_stance_density);
  REQUIRE(same.imu.accel_noise_density == nominal.imu.accel_noise_density);
  REQUIRE(same.foot_velocity_sigma == nominal.foot_velocity_sigma);
}

TEST_CASE("ex57.4.2: frontendNoise scales the contacts' covariance", "[ex57.4.2][hint 1]") {
  const FrontendNoise nominal{2e-4, 1e-3};
  Scales s;
  s.measurement_noise = 4.0;
  s.foot_process_noise = 1e3;  // not the front end's business
  const FrontendNoise n = ex57_4_2::frontendNoise(s, nominal);
  REQUIRE_REL(n.encoder_angle_sigma, 4e-4, 1e-12);
  REQUIRE_REL(n.foot_point_sigma, 2e-3, 1e-12);
}

TEST_CASE("ex57.4.2: at the nominal settings tradeoffPoint is the plain linear KF", "[ex57.4.2]") {
  const io::Log& log = trotLog();
  const auto got = ex57_4_2::tradeoffPoint(log, {}, kMatched, kWindow);
  linear_kf::LinearKf filter;
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics(), kMatched);
  const auto run = eval::runOnLog(filter, log, frontend, eval::initialState(log));
  const auto expected = eval::velocityBiasVariance(log, run.trajectory, kWindow);
  REQUIRE_REL(got.bias, expected.bias, 1e-12);
  REQUIRE_REL(got.variance, expected.variance, 1e-12);
}

// The directions of the trade-off on this trot (legkit study sweep draws the whole curves).
// (b) Trusting the model less (sigma_a^2 x 1000) passes more measurement noise through: the fast
// part grows tenfold, the slow part does not move. (c) Trusting the kinematics less (R x 1000)
// smooths more and lets the error wander: the slow part grows by half. (a) The simulated feet
// never slip, so a loose foot model only costs variance, a tight one nothing.
TEST_CASE("ex57.4.2: the noise settings trade the slow error against the fast one",
          "[ex57.4.2][hint 2]") {
  const io::Log& log = trotLog();
  const auto point = [&](double a, double b, double c) {
    return ex57_4_2::tradeoffPoint(log, {a, b, c}, kMatched, kWindow);
  };
  const auto nominal = point(1, 1, 1);

  const auto loose_model = point(1, 1e3, 1);
  REQUIRE_ABOVE(loose_model.variance, 5 * nominal.variance);
  REQUIRE_REL(loose_model.bias, nominal.bias, 0.05);

  const auto loose_kinematics = point(1, 1, 1e3);
  REQUIRE_ABOVE(loose_kinematics.bias, 1.3 * nominal.bias);

  const auto loose_feet = point(1e3, 1, 1);
  const auto tight_feet = point(1e-3, 1, 1);
  REQUIRE_ABOVE(loose_feet.variance, nominal.variance);
  REQUIRE_BELOW(tight_feet.variance, nominal.variance);
  REQUIRE_BELOW(tight_feet.bias, 1.05 * nominal.bias);
}
