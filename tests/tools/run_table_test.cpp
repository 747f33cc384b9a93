// The table of `legkit run` (tools/legkit/run_command.hpp): a failed estimator is a FAILED line
// with its file:line, time and reason under the table; non-zero health counts follow. And the
// rows its estimate files keep at a given --estimate-rate.
#include <catch2/catch.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "run_command.hpp"

using namespace legkit;

TEST_CASE("run table: failures and health counts under the table", "[cli]") {
  tools::RunRow healthy;
  healthy.run.name = "eskf";
  healthy.run.health.record(Fault::kTimeGap, 1.0);
  tools::RunRow failed;
  failed.run.name = "tsif";
  failed.run.failure = eval::RunFailure{"threw: planted", 7, 0.007, "robot.csv:10"};
  failed.run.health.record(Fault::kStateUnhealthy, 0.005);

  std::ostringstream out;
  tools::printRunTable(out, {healthy, failed});
  const std::string table = out.str();
  INFO(table);
  // tsif's own line of the table says FAILED, and only the reason follows under the table.
  const std::size_t line = table.find("\ntsif ");
  REQUIRE(line != std::string::npos);
  const std::string tsif_line = table.substr(line + 1, table.find('\n', line + 1) - line - 1);
  CHECK_THAT(tsif_line, Catch::Matchers::Contains(" FAILED "));
  CHECK_THAT(table, Catch::Matchers::Contains(
                        "FAILED tsif: robot.csv:10, t = 0.007 s (row 7): threw: planted\n"));
  CHECK_THAT(table, Catch::Matchers::Contains("health of eskf: 1 time gap\n"));
  CHECK_THAT(table, Catch::Matchers::Contains("health of tsif: 1 state unhealthy (recovered)\n"));
  // Under the table: after every estimator's line.
  CHECK(table.find("FAILED tsif:") > line);
}

namespace {

std::vector<EstimateSample> samplesAt(double rate, double duration) {
  std::vector<EstimateSample> trajectory(static_cast<std::size_t>(duration * rate) + 1);
  for (std::size_t k = 0; k < trajectory.size(); ++k) {
    trajectory[k].t = 3.0 + static_cast<double>(k) / rate;  // a log need not start at 0
  }
  return trajectory;
}

}  // namespace

TEST_CASE("run: the estimate files keep one row per period, the first and the last", "[cli]") {
  const std::vector<EstimateSample> trajectory = samplesAt(1000.0, 2.0);  // 2001 rows
  const std::vector<std::size_t> all = tools::estimateRows(trajectory, 0.0);
  REQUIRE(all.size() == trajectory.size());
  CHECK(all.back() == trajectory.size() - 1);

  const std::vector<std::size_t> kept = tools::estimateRows(trajectory, 100.0);
  REQUIRE(kept.size() == 201);  // t = 3.00, 3.01, .. 5.00
  for (std::size_t i = 0; i < kept.size(); ++i) CHECK(kept[i] == 10 * i);

  // Jittered timestamps (0.0099999 for 0.01) still give one row per period, never two.
  std::vector<EstimateSample> jittered = trajectory;
  for (std::size_t k = 0; k < jittered.size(); ++k) jittered[k].t += (k % 2 ? -1e-9 : 1e-9);
  CHECK(tools::estimateRows(jittered, 100.0).size() == 201);

  // A rate that does not divide the log's: the last row is kept even off the grid.
  const std::vector<std::size_t> odd = tools::estimateRows(samplesAt(1000.0, 0.25), 3.0);
  CHECK(odd == std::vector<std::size_t>{0, 250});
  // A rate above the log's keeps every row.
  CHECK(tools::estimateRows(trajectory, 5000.0).size() == trajectory.size());
  CHECK(tools::estimateRows({}, 100.0).empty());
}

TEST_CASE("run table: metrics not computed print as n/c, the truth's masking and velocity",
          "[cli]") {
  tools::RunRow still;
  still.run.name = "eskf";
  eval::Metrics m;
  m.position_rmse = 0.012;
  m.drift_percent = eval::kNotComputed;       // a truth that never moved
  m.rpe.push_back(eval::RelativeError{1.0});  // no pair over 1 m: not computed
  m.ate_se3_rmse = 0.004;
  m.ate_4dof_rmse = eval::kNotComputed;
  m.distance = 0.0;
  m.scored_rows = 900;
  m.masked_rows = 100;
  m.velocity_differentiated = true;
  m.velocity_method = "central difference of gt_p";
  still.metrics = m;

  std::ostringstream out;
  tools::printRunTable(out, {still});
  const std::string table = out.str();
  INFO(table);
  const std::size_t line = table.find("\neskf ");
  REQUIRE(line != std::string::npos);
  const std::string eskf_line = table.substr(line + 1, table.find('\n', line + 1) - line - 1);
  CHECK_THAT(eskf_line, Catch::Matchers::Contains(" n/c "));
  CHECK_THAT(eskf_line, Catch::Matchers::Contains(" 0.012 "));
  CHECK_THAT(eskf_line, Catch::Matchers::Contains(" 0.004 "));  // ATE after the SE(3) alignment
  CHECK_THAT(table, Catch::Matchers::Contains(" ATE se3 [m]  RPE 1m [%] "));
  CHECK_THAT(table,
             Catch::Matchers::Contains("\nATE se3: after the least-squares SE(3) alignment"));
  CHECK_THAT(table, !Catch::Matchers::Contains("nan"));
  CHECK_THAT(table,
             Catch::Matchers::Contains(
                 "truth: 100 rows masked (gt_valid = 0); velocity: central difference of gt_p\n"));
  CHECK(table.find("truth: ") > line);

  const nlohmann::json j = tools::toJson({still}).at(0);
  CHECK(j.at("drift_percent").dump() == "null");  // NaN is written as null
  CHECK(j.at("rpe").at(0).at("computed") == false);
  CHECK(j.at("ate_se3_rmse_m") == 0.004);
  CHECK(j.at("ate_4dof_rmse_m").dump() == "null");
  CHECK(j.at("rpe").at(0).at("translation_rmse_m").dump() == "null");
  CHECK(j.at("distance_m") == 0.0);
  CHECK(j.at("scored_rows") == 900);
  CHECK(j.at("masked_rows") == 100);
  CHECK(j.at("truth_velocity") == "central difference of gt_p");

  // A truth with every row valid and its own velocity: no truth line.
  m.masked_rows = 0;
  m.velocity_differentiated = false;
  still.metrics = m;
  std::ostringstream plain;
  tools::printRunTable(plain, {still});
  CHECK_THAT(plain.str(), !Catch::Matchers::Contains("truth: "));
}

TEST_CASE("initial state: the first valid truth row, a pose-only truth's velocity differentiated",
          "[cli]") {
  // 1 s at 100 Hz, moving at (0.5, -0.2, 0) m/s, yawed 30 deg; the first 5 rows a dropout whose
  // pose is zero (a zero quaternion).
  io::Log log;
  log.layout.ground_truth = true;
  log.layout.gt_valid = true;
  log.layout.gt_velocity = false;
  const Eigen::Vector3d v(0.5, -0.2, 0.0);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.5235987755982988, Eigen::Vector3d::UnitZ()));
  for (int k = 0; k <= 100; ++k) {
    io::LogRow row;
    row.t = 2.0 + 0.01 * k;
    row.gt_valid = k >= 5;
    row.gt_p = row.gt_valid ? Eigen::Vector3d(1.0, 2.0, 0.3) + v * (0.01 * k) : Eigen::Vector3d();
    row.gt_q = row.gt_valid ? q : Eigen::Quaterniond(0.0, 0.0, 0.0, 0.0);
    log.rows.push_back(row);
  }
  const EstimateSample x0 = eval::initialState(log);
  CHECK(x0.t == 2.0);  // the run still starts at row 0
  CHECK(x0.q.angularDistance(q) < 1e-12);
  CHECK((x0.p - log.rows[5].gt_p).norm() < 1e-12);
  CHECK((x0.v - v).norm() < 1e-9);  // the pose differentiated, not the zero gt_v

  // A truth with its own velocity takes gt_v from the same row.
  log.layout.gt_velocity = true;
  for (io::LogRow& row : log.rows) row.gt_v = Eigen::Vector3d(0.1, 0.0, 0.0);
  CHECK((eval::initialState(log).v - Eigen::Vector3d(0.1, 0.0, 0.0)).norm() == 0.0);
}
