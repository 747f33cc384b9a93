// Recorded logs through `legkit run --log` (issue 22 items 4 and 7): a log without joint velocity
// columns, the truth's differentiation window, a planned gait from the settings, the contact
// flags in the estimate files, and the simulation's options said to have no effect.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "io/log_reader.hpp"
#include "io/log_writer.hpp"
#include "legkit_cli.hpp"

namespace fs = std::filesystem;
using namespace legkit;

namespace {

using test::runLegkit;
constexpr auto summary = test::readSummary;

// A 3 s analytic trot recorded by `legkit sim` as trot.csv in dir, and read back.
io::Log recordTrot(const fs::path& dir) {
  std::string output;
  REQUIRE(runLegkit(
              dir,
              {"sim", "--scenario", "trot", "--duration", "3", "--seed", "3", "--out", "trot.csv"},
              output) == 0);
  return io::readLog((dir / "trot.csv").string());
}

// The rows of a CSV file after its comment lines, split at commas (the header first).
std::vector<std::vector<std::string>> csvRows(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream s(line);
    for (std::string field; std::getline(s, field, ',');) fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

const std::vector<std::string> kQuiet = {"--no-plots", "--estimate-rate", "all"};

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

TEST_CASE("legkit run: a log without joint velocities differentiates its angles",
          "[cli][real-robot]") {
  const test::ScratchFolder dir("real_logs_angles");
  io::Log log = recordTrot(dir.path);
  log.layout.joint_velocity = false;
  io::writeLog((dir.path / "angles.csv").string(), log);
  std::string output;
  REQUIRE(runLegkit(dir.path, with({"run", "--log", "angles.csv", "--out", "a"}, kQuiet), output) !=
          1);
  INFO(output);
  CHECK_THAT(output, Catch::Matchers::Contains(
                         "joint velocities differentiated from the angles (the log has none)"));
  CHECK(summary(dir.path / "a")["frontend"].get<std::string>().find("(the log has none)") !=
        std::string::npos);

  std::ofstream(dir.path / "logged.yaml") << "frontend:\n  joint_velocities: logged\n";
  CHECK(runLegkit(
            dir.path,
            with({"run", "--log", "angles.csv", "--config", "logged.yaml", "--out", "b"}, kQuiet),
            output) == 2);
  CHECK_THAT(output, Catch::Matchers::Contains("frontend.joint_velocities") &&
                         Catch::Matchers::Contains("no joint velocity columns"));
}

TEST_CASE("legkit run --contact gait-clock: the planned gait from contact.gait",
          "[cli][real-robot]") {
  const test::ScratchFolder dir("real_logs_gait");
  recordTrot(dir.path);
  std::string output;
  CHECK(
      runLegkit(dir.path,
                with({"run", "--log", "trot.csv", "--contact", "gait-clock", "--out", "n"}, kQuiet),
                output) == 1);
  CHECK_THAT(output, Catch::Matchers::Contains("needs a gait schedule") &&
                         Catch::Matchers::Contains("contact.gait"));

  std::ofstream(dir.path / "gait.yaml")
      << "contact:\n  gait:\n    period: 0.5\n    duty: 0.6\n    offsets: [0, 0.5, 0.5, 0]\n";
  const int status = runLegkit(dir.path,
                               with({"run", "--log", "trot.csv", "--config", "gait.yaml",
                                     "--contact", "gait-clock", "--out", "g"},
                                    kQuiet),
                               output);
  INFO(output);
  CHECK((status == 0 || status == 3));
  CHECK_THAT(output, Catch::Matchers::Contains("detected by gait-clock"));
  CHECK(summary(dir.path / "g")["contacts"]["source"] == "gait-clock");

  // Offsets for another number of feet: the key and the file.
  std::ofstream(dir.path / "three.yaml")
      << "contact:\n  gait:\n    period: 0.5\n    offsets: [0, 0.5, 0.5]\n";
  CHECK(runLegkit(dir.path,
                  with({"run", "--log", "trot.csv", "--config", "three.yaml", "--contact",
                        "gait-clock", "--out", "t"},
                       kQuiet),
                  output) == 2);
  CHECK_THAT(output, Catch::Matchers::Contains("three.yaml: contact.gait.offsets: 3 offsets") &&
                         Catch::Matchers::Contains("4 feet"));
}

TEST_CASE("legkit run: each estimate file has the contact flags its estimator was given",
          "[cli][real-robot]") {
  const test::ScratchFolder dir("real_logs_contacts");
  const io::Log log = recordTrot(dir.path);
  std::string output;
  // The log's own flags, untouched (no settling, no slip reaction): the columns are the log's.
  REQUIRE(runLegkit(dir.path,
                    with({"run", "--log", "trot.csv", "--contact", "truth", "--slip", "none",
                          "--settle", "0", "--out", "c"},
                         kQuiet),
                    output) == 0);
  INFO(output);
  for (const char* name : {"eskf", "leg-odometry"}) {
    const auto rows = csvRows(dir.path / "c" / (std::string("estimate_") + name + ".csv"));
    REQUIRE(rows.size() == log.rows.size() + 1);
    const std::vector<std::string>& header = rows.front();
    REQUIRE(header.size() >= 4);
    const std::size_t first = header.size() - 4;
    for (int foot = 0; foot < 4; ++foot) {
      CHECK(header[first + foot] == "contact_" + std::to_string(foot));
    }
    for (std::size_t k = 0; k < log.rows.size(); ++k) {
      for (int foot = 0; foot < 4; ++foot) {
        REQUIRE(rows[k + 1][first + foot] == (log.rows[k].contact[foot] ? "1" : "0"));
      }
    }
  }
}

TEST_CASE("legkit run: frontend.truth_velocity_window differentiates a pose-only truth",
          "[cli][real-robot]") {
  const test::ScratchFolder dir("real_logs_window");
  io::Log log = recordTrot(dir.path);
  log.layout.gt_velocity = false;
  io::writeLog((dir.path / "pose.csv").string(), log);
  std::ofstream(dir.path / "wide.yaml") << "frontend:\n  truth_velocity_window: 0.3\n";
  std::string output;
  const std::vector<std::string> run = {"run",    "--log", "pose.csv", "--contact", "truth",
                                        "--slip", "none",  "--settle", "0"};
  REQUIRE(runLegkit(dir.path, with(with(run, {"--out", "d"}), kQuiet), output) == 0);
  REQUIRE(runLegkit(dir.path, with(with(run, {"--config", "wide.yaml", "--out", "w"}), kQuiet),
                    output) == 0);
  INFO(output);
  const nlohmann::json d = summary(dir.path / "d")["estimators"][3];
  const nlohmann::json w = summary(dir.path / "w")["estimators"][3];
  CHECK_THAT(d["truth_velocity"].get<std::string>(), Catch::Matchers::Contains("0.05 s"));
  CHECK_THAT(w["truth_velocity"].get<std::string>(), Catch::Matchers::Contains("0.3 s"));
  CHECK(d["velocity_rmse_mps"] != w["velocity_rmse_mps"]);
  CHECK(d["anees"] != w["anees"]);

  std::ofstream(dir.path / "zero.yaml") << "frontend:\n  truth_velocity_window: 0\n";
  CHECK(runLegkit(dir.path, with(with(run, {"--config", "zero.yaml", "--out", "z"}), kQuiet),
                  output) != 0);
  CHECK_THAT(output, Catch::Matchers::Contains("zero.yaml:2") &&
                         Catch::Matchers::Contains("truth_velocity_window"));
}

TEST_CASE("legkit run --log: --scenario, --duration and --seed are said to have no effect",
          "[cli][real-robot]") {
  const test::ScratchFolder dir("real_logs_unused");
  recordTrot(dir.path);
  std::string output;
  REQUIRE(runLegkit(dir.path,
                    with({"run", "--log", "trot.csv", "--scenario", "walk", "--duration", "5",
                          "--seed", "7", "--out", "u"},
                         kQuiet),
                    output) != 1);
  CHECK_THAT(output, Catch::Matchers::Contains("warning: --scenario has no effect on a recorded "
                                               "log"));
  CHECK_THAT(output, Catch::Matchers::Contains("warning: --duration has no effect"));
  CHECK_THAT(output, Catch::Matchers::Contains("warning: --seed has no effect"));
  REQUIRE(runLegkit(dir.path, with({"run", "--log", "trot.csv", "--out", "v"}, kQuiet), output) !=
          1);
  CHECK_THAT(output, !Catch::Matchers::Contains("warning"));
}
