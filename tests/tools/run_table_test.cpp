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
