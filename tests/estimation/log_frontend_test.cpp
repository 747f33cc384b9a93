// The log front end and the baseline estimators on simulated logs: what the estimators are fed
// must agree with the simulator's ground truth.
#include <catch2/catch.hpp>

#include "estimation/imu/dead_reckoning_estimator.hpp"
#include "estimation/leg_odometry/leg_odometry_estimator.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "sim/simulator.hpp"

using namespace legkit;

namespace {

io::Log noiselessTrot(double duration) {
  sim::SimOptions options;
  options.scenario = sim::scenarioByName("trot");
  options.duration = duration;
  options.noiseless();
  return sim::simulate(options).log;
}

}  // namespace

TEST_CASE("stance contacts are the true feet seen from the true body", "[57.3]") {
  const io::Log log = noiselessTrot(3.0);
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  // A stance foot stays put in the world, so d = p + R r must be the same at every row of one
  // stance; check it against the foot position at the stance's first row.
  std::array<std::optional<Eigen::Vector3d>, 4> anchor;
  int checked = 0;
  for (const io::LogRow& row : log.rows) {
    const StepInput in = frontend.input(row, 1e-3);
    std::array<bool, 4> down{};
    for (const ContactMeasurement& c : in.stance()) {
      const Eigen::Vector3d d = row.gt_p + row.gt_q * c.p_body;
      if (!anchor[c.foot]) anchor[c.foot] = d;
      CHECK((d - *anchor[c.foot]).norm() < 1e-9);
      REQUIRE(c.v_body.has_value());
      // ...and its world velocity is zero: v + R (w x r + r_dot) = 0.
      const Eigen::Vector3d w_b = row.gyro;
      CHECK((row.gt_v + row.gt_q * (w_b.cross(c.p_body) + *c.v_body)).norm() < 1e-9);
      down[c.foot] = true;
      ++checked;
    }
    for (int f = 0; f < 4; ++f)
      if (!down[f]) anchor[f].reset();
  }
  CHECK(checked > 1000);
}

TEST_CASE("leg odometry tracks a noiseless trot; dead reckoning stays exact without noise",
          "[57.3]") {
  const io::Log log = noiselessTrot(4.0);
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  const EstimateSample x0 = eval::initialState(log);

  imu::DeadReckoningEstimator dr;
  const auto drMetrics = eval::compare(log, eval::runOnLog(dr, log, frontend, x0).trajectory);
  // Exact-step integration of piecewise-constant input: only the zero-order hold of the IMU
  // sample between rows separates it from the smooth truth.
  CHECK(drMetrics.position_rmse < 0.05);

  leg_odometry::LegOdometryEstimator lo;
  const auto loMetrics = eval::compare(log, eval::runOnLog(lo, log, frontend, x0).trajectory);
  CHECK(loMetrics.velocity_rmse < 0.01);
  CHECK(loMetrics.position_rmse < 0.01);
  CHECK(loMetrics.position_rmse < drMetrics.position_rmse);
}

TEST_CASE("a log with neither joints nor feet is refused", "[57.3]") {
  io::LogLayout layout;
  layout.joints = false;
  CHECK_THROWS_WITH(LogFrontend(layout, model::QuadrupedKinematics()),
                    Catch::Contains("neither joint nor foot"));
}
