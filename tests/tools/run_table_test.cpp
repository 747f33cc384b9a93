// The table of `legkit run` (tools/legkit/run_command.hpp): a failed estimator is a FAILED line
// with its file:line, time and reason under the table; non-zero health counts follow.
#include <catch2/catch.hpp>
#include <sstream>
#include <string>

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
