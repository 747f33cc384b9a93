// The closed-loop adapter (tools/legkit/closed_loop.hpp) hands the controller exactly what
// `legkit run` would report for that estimator, row by row.
#include <catch2/catch.hpp>

#include "closed_loop.hpp"
#include "estimation/estimators.hpp"
#include "eval/runner.hpp"
#include "sim/simulator.hpp"

namespace {

legkit::io::Log analyticTrot(bool ground_truth) {
  legkit::sim::SimOptions options;
  options.duration = 1.5;
  options.ground_truth = ground_truth;
  return legkit::sim::simulate(options).log;
}

}  // namespace

TEST_CASE("closed loop: the adapter's estimate is the estimator's on the same rows", "[cli]") {
  const legkit::io::Log log = analyticTrot(true);
  const legkit::FrontendNoise noise;
  for (const std::string& name : {std::string("leg-odometry"), std::string("invariant-ekf")}) {
    INFO(name);
    legkit::tools::EstimatorBaseState source(name, log.layout, noise);
    const std::unique_ptr<legkit::Estimator> reference = legkit::makeEstimator(name);
    const legkit::eval::RunResult run = legkit::eval::runOnLog(
        *reference, log,
        legkit::LogFrontend(log.layout, legkit::model::QuadrupedKinematics(), noise),
        legkit::eval::initialState(log));
    REQUIRE(run.trajectory.size() == log.rows.size());
    double worst = 0.0;
    for (std::size_t k = 0; k < log.rows.size(); ++k) {
      legkit::sim::BaseEstimate out;
      REQUIRE(source.update(log.rows[k], out));
      const legkit::EstimateSample& x = run.trajectory[k];
      worst = std::max({worst, (out.p - x.p).norm(), (out.v - x.v).norm(),
                        (out.R - x.q.toRotationMatrix()).norm()});
    }
    CHECK(worst == 0.0);
    // It followed the robot: the trot's first 3 cm, to within a centimetre.
    const double x_true = log.rows.back().gt_p.x();
    CHECK(x_true > 0.03);
    CHECK(source.estimator().estimate().p.x() == Approx(x_true).margin(0.01));
  }
}

TEST_CASE("closed loop: without ground truth it starts level-from-gravity at the origin", "[cli]") {
  const legkit::io::Log log = analyticTrot(false);
  legkit::tools::EstimatorBaseState source("eskf", legkit::tools::physicsLogLayout(false), {});
  legkit::sim::BaseEstimate out;
  REQUIRE(source.update(log.rows[0], out));
  CHECK(out.p.norm() < 1e-6);
  // The body z axis seen in the world is the accelerometer's up direction.
  const Eigen::Vector3d up = out.R.transpose() * Eigen::Vector3d::UnitZ();
  CHECK(up.dot(log.rows[0].acc.normalized()) == Approx(1.0).margin(1e-9));
  CHECK_THROWS_AS(legkit::tools::EstimatorBaseState("no-such-filter", log.layout, {}),
                  std::invalid_argument);
}
