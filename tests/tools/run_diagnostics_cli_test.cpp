// `legkit run`'s per-foot contact diagnostics in summary.json (issue 22 item 7): the shares of
// the fallback chain's detectors add up, and a foot whose force sensor fails part-way is handed
// down the chain, counted with the problem that did it. And the stance-foot NIS (issue 22 item
// 3): a run whose settings call the legs exact warns that they do not fit the log.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
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

// A 3 s physics trot, `trot.csv` in dir: the log both tests run on.
void simulateTrot(const fs::path& dir) {
  std::string output;
  REQUIRE(runLegkit(dir,
                    {"sim", "--scenario", "physics-trot", "--duration", "3", "--out", "trot.csv"},
                    output) == 0);
}

}  // namespace

TEST_CASE("legkit run: per-foot contact diagnostics add up; a failed sensor hands its foot over",
          "[cli][57.6]") {
  const test::ScratchFolder dir("run-diagnostics");
  std::string output;
  simulateTrot(dir.path);
  io::Log log = io::readLog((dir.path / "trot.csv").string());
  REQUIRE(log.layout.force);
  // FL's force sensor reads -50 N (a faulty sensor: below the Schmitt trigger's negative limit)
  // from 2 s on: the Schmitt trigger cannot decide FL any more and hands it down the chain.
  for (io::LogRow& row : log.rows) {
    if (row.t >= 2.0) row.force[0] = -50.0;
  }
  {
    std::ofstream f(dir.path / "broken.csv");
    io::writeLog(f, log);
  }
  const int status =
      runLegkit(dir.path, {"run", "--log", "broken.csv", "--no-plots", "--out", "out"}, output);
  INFO(output);
  REQUIRE((status == 0 || status == 3));
  CHECK(output.find("contacts per foot") != std::string::npos);
  const nlohmann::json s = summary(dir.path / "out");
  for (const nlohmann::json& e : s["estimators"]) {
    INFO(e["estimator"]);
    REQUIRE(e["feet"].size() == 4);
    for (const nlohmann::json& foot : e["feet"]) {
      const nlohmann::json& c = foot["contact"];
      double total = c["undecided"].get<double>();
      for (const auto& [name, share] : c["decided_by"].items()) total += share.get<double>();
      CHECK(total == Approx(1.0).margin(1e-12));
      CHECK(c["samples"] == log.rows.size());
      CHECK(c["stance_share"].get<double>() > 0.3);
      CHECK(c["touchdowns"].get<long>() > 0);
    }
    const nlohmann::json& fl = e["feet"][0]["contact"];
    CHECK(e["feet"][0]["name"] == "FL");
    // About a third of the run (2 s to 3 s) decided by a later detector.
    CHECK(fl["decided_by"]["schmitt"].get<double>() == Approx(2.0 / 3.0).margin(0.01));
    CHECK(fl["handovers_down"].get<long>() >= 1);
    CHECK(fl["handovers"].get<long>() >= fl["handovers_down"].get<long>());
    CHECK(fl["handover_problem"] == "force negative");
    // The healthy feet stay with the Schmitt trigger.
    for (int foot = 1; foot < 4; ++foot) {
      CHECK(e["feet"][foot]["contact"]["decided_by"]["schmitt"] == 1.0);
      CHECK(e["feet"][foot]["contact"]["handovers"] == 0);
    }
  }
}

TEST_CASE("legkit run: stance-foot innovations larger than their covariance are said",
          "[cli][real-robot]") {
  const test::ScratchFolder dir("run-nis");
  std::string output;
  simulateTrot(dir.path);
  const std::vector<std::string> run = {"run", "--log", "trot.csv", "--no-plots"};
  const auto with = [](std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  // The kit's defaults fit: no warning, and summary.json's verdicts are not over-confident.
  REQUIRE(runLegkit(dir.path, with(run, {"--out", "d"}), output) == 0);
  CHECK(output.find("legkit tune") == std::string::npos);
  // The summary is held in a local: a range-for over a temporary's member dangles.
  const nlohmann::json defaults = summary(dir.path / "d");
  for (const nlohmann::json& e : defaults["estimators"]) {
    if (e.contains("stance_nis") && !e["stance_nis"].is_null()) {
      CHECK(e["stance_nis"]["verdict"] != "over-confident");
    }
  }
  // Encoders and feet called exact (1 um): the innovations say otherwise.
  test::writeFile(dir.path / "exact.yaml",
                  "feet:\n  stance_density: 1.0e-5\nfrontend:\n  encoder_angle_sigma: 1.0e-6\n"
                  "  foot_point_sigma: 1.0e-6\n");
  REQUIRE(runLegkit(dir.path, with(run, {"--config", "exact.yaml", "--out", "x"}), output) >= 0);
  INFO(output);
  CHECK(output.find("eskf: stance-foot innovations") != std::string::npos);
  CHECK(output.find("run `legkit tune` on it") != std::string::npos);
  const nlohmann::json exact = summary(dir.path / "x");
  for (const nlohmann::json& e : exact["estimators"]) {
    if (e["estimator"] == "eskf") CHECK(e["stance_nis"]["verdict"] == "over-confident");
  }
}
