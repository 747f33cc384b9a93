// `legkit study fusion --quick` end to end (section 57.8): a 30 s physics trot around the circle
// with simulated SLAM poses; the program writes what it says it writes, every coupling's figures
// are finite, and loose coupling beats proprioception alone.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "scratch_folder.hpp"

namespace fs = std::filesystem;

namespace {

using legkit::test::ScratchFolder;
using nlohmann::json;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) cells.push_back(cell);
  return cells;
}

}  // namespace

TEST_CASE("study fusion --quick: table, summary.json and trace written, every figure finite",
          "[cli][fusion][57.8]") {
  ScratchFolder dir("study_fusion");
  const legkit::test::ProgramResult r = legkit::test::runProgram(
      dir.path, {LEGKIT_EXE, "study", "fusion", "--quick", "--no-plots", "--out", "out"});
  INFO(r.output);
  REQUIRE(r.status == 0);

  std::ifstream summary_file(dir.path / "out" / "summary.json");
  REQUIRE(summary_file);
  const json summary = json::parse(summary_file);
  CHECK(summary.at("duration_s").get<double>() == 30.0);
  CHECK(summary.at("distance_m").get<double>() > 10.0);  // 0.5 m/s after 2 s of start
  const json& couplings = summary.at("couplings");
  REQUIRE(couplings.size() >= 1);
  std::vector<std::string> names;
  for (const json& c : couplings) {
    const std::string name = c.at("name").get<std::string>();
    names.push_back(name);
    INFO(name);
    CHECK(r.output.find(name) != std::string::npos);  // a row of the printed table
    for (const char* key : {"ate_m", "position_rmse_m", "rpe_percent", "rpe_deg",
                            "final_yaw_error_deg", "yaw_rmse_deg"}) {
      INFO(key);
      REQUIRE(c.at(key).is_number());
      CHECK(std::isfinite(c.at(key).get<double>()));
    }
    CHECK(c.at("ate_m").get<double>() >= 0.0);
  }
  REQUIRE(names.size() >= 4);
  CHECK(names[0] == "proprio");
  CHECK(names[1] == "loose");
  // Poses every 0.1 s bound the drift: loose coupling beats proprioception alone in ATE.
  CHECK(couplings[1].at("ate_m").get<double>() < couplings[0].at("ate_m").get<double>());
  CHECK(couplings[1].at("poses_used").get<int>() > 200);  // of about 300
  // Pose injection (DelayedFilter): every pose applied at its stamp, also ahead of proprioception.
  CHECK(names[2] == "injection");
  CHECK(couplings[2].at("poses_used").get<int>() > 200);
  CHECK(couplings[2].at("ate_m").get<double>() < couplings[0].at("ate_m").get<double>());
  // The fixed-lag smoother: every pose attached (none older than its 2 s window).
  CHECK(names[3] == "smoother");
  CHECK(couplings[3].at("poses_used").get<int>() > 200);

  // The trace: one row per 0.1 s, four columns per coupling, every cell a finite number.
  std::ifstream trace(dir.path / "out" / "fusion-trace.csv");
  REQUIRE(trace);
  std::string line;
  REQUIRE(std::getline(trace, line));
  const std::vector<std::string> header = split(line);
  REQUIRE(header.size() == 4 + 4 * names.size());
  for (std::size_t i = 0; i < names.size(); ++i) CHECK(header[4 + 4 * i] == names[i] + "_x");
  int rows = 0;
  while (std::getline(trace, line)) {
    const std::vector<std::string> cells = split(line);
    REQUIRE(cells.size() == header.size());
    for (const std::string& cell : cells) REQUIRE(std::isfinite(std::stod(cell)));
    ++rows;
  }
  CHECK(rows >= 299);
  CHECK(rows <= 301);
}
