// Exercise 57.9.2: the choice per scenario, each backed by a proprioceptive run of the kit on a
// simulated trot (the analytic simulator, 10 s at 1 kHz, seed 5792).
#include <catch2/catch.hpp>
#include <cmath>

#include "estimation/estimators.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "ex57_9_2.hpp"
#include "exercises/exercise_check.hpp"
#include "model/quadruped.hpp"
#include "sim/simulator.hpp"

using ex57_9_2::Choice;
using ex57_9_2::Drift;
using ex57_9_2::Scenario;

namespace {

// One simulated trot, shared by the test cases (simulating it is the slow part).
const legkit::io::Log& trotLog() {
  static const legkit::io::Log log = [] {
    legkit::sim::SimOptions options;
    options.scenario = legkit::sim::scenarioByName("trot");
    options.duration = 10.0;
    options.seed = 5792;
    return legkit::sim::simulate(options).log;
  }();
  return log;
}

// The same figures, recomputed here with the kit.
Drift kitDrift(const std::string& name) {
  const legkit::io::Log& log = trotLog();
  const auto filter = legkit::makeEstimator(name);
  const legkit::LogFrontend frontend(log.layout, legkit::model::QuadrupedKinematics());
  const auto run = legkit::eval::runOnLog(*filter, log, frontend, legkit::eval::initialState(log));
  Drift d;
  for (std::size_t k = 1; k < log.rows.size(); ++k)
    d.distance += (log.rows[k].gt_p - log.rows[k - 1].gt_p).norm();
  d.position_error = (run.trajectory.back().p - log.rows.back().gt_p).norm();
  d.yaw_error_deg = std::abs(legkit::eval::yawError(run.trajectory.back().q.toRotationMatrix(),
                                                    log.rows.back().gt_q.toRotationMatrix())) *
                    180.0 / M_PI;
  return d;
}

}  // namespace

TEST_CASE("57.9.2 drift is the kit's run, measured from the truth", "[ex57.9.2][hint 1]") {
  for (const std::string name : {"linear-kf", "invariant-ekf"}) {
    const Drift got = ex57_9_2::drift(trotLog(), name), expected = kitDrift(name);
    INFO(name << ": " << got.distance << " m travelled, final error " << got.position_error
              << " m, yaw " << got.yaw_error_deg << " deg");
    REQUIRE_NEAR(got.distance, expected.distance, 1e-9);
    REQUIRE_NEAR(got.position_error, expected.position_error, 1e-9);
    REQUIRE_NEAR(got.yaw_error_deg, expected.yaw_error_deg, 1e-9);
  }
}

TEST_CASE("57.9.2 (a) factory patrol: the simplest filter is as good on flat ground",
          "[ex57.9.2][hint 2]") {
  REQUIRE(ex57_9_2::choose(Scenario::kFactoryPatrol) == Choice::kLinearKf);
  const Drift kf = kitDrift("linear-kf"), inekf = kitDrift("invariant-ekf");
  const double kf_per_m = kf.position_error / kf.distance;
  const double inekf_per_m = inekf.position_error / inekf.distance;
  INFO("final error per metre travelled: linear KF " << 100 * kf_per_m << " %, InEKF "
                                                     << 100 * inekf_per_m << " %");
  // A few mm per metre: a patrol re-localised at a charging dock every 100 m stays within a metre.
  REQUIRE_BELOW(kf_per_m, 0.01);
  // The InEKF's attitude in the state buys nothing here (the attitude starts right on flat ground).
  REQUIRE_BELOW(kf_per_m, 2.0 * inekf_per_m);
}

TEST_CASE("57.9.2 (b) mine: a kilometre of proprioception alone drifts by metres",
          "[ex57.9.2][hint 2]") {
  const Choice c = ex57_9_2::choose(Scenario::kMineExploration);
  const Drift best = kitDrift("invariant-ekf");  // the best proprioceptive filter of the guide
  const double over_1km = best.position_error / best.distance * 1000.0;
  INFO("InEKF drift extrapolated to 1 km: " << over_1km << " m");
  REQUIRE(over_1km > 1.0);
  // Only an estimator with the LiDAR in it closes that gap.
  REQUIRE((c == Choice::kModularLidarEkf || c == Choice::kFactorGraph));
}

TEST_CASE("57.9.2 (c) humanoid on a building site: centimetres need exteroception",
          "[ex57.9.2][hint 2]") {
  REQUIRE(ex57_9_2::choose(Scenario::kHumanoidBuilding) == Choice::kFactorGraph);
  const Drift kf = kitDrift("linear-kf"), inekf = kitDrift("invariant-ekf");
  const double best_per_m =
      std::min(kf.position_error / kf.distance, inekf.position_error / inekf.distance);
  INFO("the better filter's error after walking 10 m to the work place: "
       << 10.0 * best_per_m << " m; yaw after 10 s: " << kf.yaw_error_deg << " / "
       << inekf.yaw_error_deg << " deg");
  // Ten metres of walking already put the base (and the hand with it) beyond a centimetre, and
  // nothing in legs and IMU bounds the heading (yaw is unobservable, 57.2).
  REQUIRE(10.0 * best_per_m > 0.01);
}
