// `legkit study contact` and `legkit study slip` end to end on short physics runs. Contact: one
// row per physics scenario and detector, scores in range, the Schmitt trigger on the foot sensor
// finds the trot's contacts well (57.6). Slip: one row per scenario, filter and reaction; the push
// on ice found and handled, the terrain called ice (57.7).
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "estimation/contact/detectors.hpp"
#include "scratch_folder.hpp"
#include "spawn.hpp"

namespace fs = std::filesystem;

namespace {

using Folder = legkit::test::ScratchFolder;
using legkit::test::slurp;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) cells.push_back(cell);
  return cells;
}

// The rows of a CSV written by legkit study (comment lines skipped) as column -> cell.
std::vector<std::map<std::string, std::string>> readCsv(const fs::path& path) {
  std::ifstream f(path);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header.empty()) {
      header = split(line);
      continue;
    }
    const std::vector<std::string> cells = split(line);
    REQUIRE(cells.size() == header.size());
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

// Both on a subset of their scenarios (--scenarios, --filters): the full studies take minutes
// under the sanitizers; every scenario runs through the same code.
TEST_CASE(
    "study contact: every chosen scenario x detector scored, Schmitt finds the trot's contacts",
    "[cli][57.6]") {
  Folder dir("study_contact");
  const fs::path output = dir.path / "output.txt";
  const int status =
      legkit::test::spawnAndWait({LEGKIT_EXE, "study", "contact", "--duration", "2", "--scenarios",
                                  "physics-trot,physics-ice", "--no-plots", "--out", "out"},
                                 dir.path.string(), output.string());
  const std::string text = slurp(output);
  INFO(text);
  REQUIRE(status == 0);

  const std::vector<std::string> scenarios = {"physics-trot", "physics-ice"};
  const std::vector<std::string> detectors = legkit::contact::detectorNames();
  const auto rows = readCsv(dir.path / "out" / "contact.csv");
  REQUIRE(rows.size() == scenarios.size() * detectors.size());
  std::map<std::string, std::map<std::string, std::string>> by_pair;
  for (const auto& r : rows) {
    by_pair[r.at("scenario") + " " + r.at("detector")] = r;
    const double f1 = std::stod(r.at("f1"));
    INFO(r.at("scenario") << " " << r.at("detector") << ": F1 " << f1);
    CHECK(f1 >= 0.0);
    CHECK(f1 <= 1.0);
    // Precision is undefined (NaN) for a detector that never says contact.
    const double precision = std::stod(r.at("precision")), recall = std::stod(r.at("recall"));
    CHECK((std::isnan(precision) || (precision >= 0.0 && precision <= 1.0)));
    CHECK((recall >= 0.0 && recall <= 1.0));
    CHECK(std::stod(r.at("chatter_per_min")) >= 0.0);
  }
  for (const std::string& s : scenarios) {
    for (const std::string& d : detectors) CHECK(by_pair.count(s + " " + d) == 1);
  }
  for (const std::string& d : detectors) CHECK(text.find(d) != std::string::npos);

  // The chapter's Schmitt trigger (50 N / 20 N, 5 ms / 5 ms) on the foot sensor, over the trot's
  // first second of gait: nearly every contact sample found, touchdowns found within 20 ms.
  const auto& schmitt = by_pair.at("physics-trot schmitt");
  CHECK(std::stod(schmitt.at("f1")) > 0.9);
  CHECK(std::stod(schmitt.at("touchdown_delay_mean_ms")) >= 0.0);
  CHECK(std::stod(schmitt.at("touchdown_delay_mean_ms")) < 20.0);
  CHECK(std::stoi(schmitt.at("missed_touchdowns")) == 0);
}

TEST_CASE(
    "study slip: every chosen scenario x filter x reaction, the push on ice found and handled",
    "[cli][57.7]") {
  Folder dir("study_slip");
  const fs::path output = dir.path / "output.txt";
  // 4 s: physics-ice-push runs to 4.2 s, 1 s after its push.
  const int status =
      legkit::test::spawnAndWait({LEGKIT_EXE, "study", "slip", "--duration", "4", "--scenarios",
                                  "physics-ice-push,physics-trot", "--filters",
                                  "eskf,invariant-ekf", "--no-plots", "--out", "out"},
                                 dir.path.string(), output.string());
  const std::string text = slurp(output);
  INFO(text);
  REQUIRE(status == 0);

  const auto rows = readCsv(dir.path / "out" / "slip.csv");
  REQUIRE(rows.size() == 2 * 2 * 4);  // scenarios x filters x reactions
  std::map<std::string, std::map<std::string, std::string>> by;
  for (const auto& r : rows)
    by[r.at("scenario") + " " + r.at("filter") + " " + r.at("reaction")] = r;
  // Every foot slides when pushed on ice; the check finds each slide within 50 ms.
  const auto& none = by.at("physics-ice-push eskf none");
  CHECK(std::stoi(none.at("slips")) >= 4);
  CHECK(none.at("detected") == none.at("slips"));
  CHECK(std::stod(none.at("delay_p95_ms")) < 50.0);
  // IMU only while every foot slides: the ESKF's velocity error well below the one that trusts
  // the sliding legs.
  CHECK(std::stod(by.at("physics-ice-push eskf imu-only").at("velocity_rmse")) <
        0.6 * std::stod(none.at("velocity_rmse")));

  const auto terrain = readCsv(dir.path / "out" / "slip-terrain.csv");
  REQUIRE(terrain.size() == 2);
  for (const auto& r : terrain) {
    if (r.at("scenario") != "physics-ice-push") continue;
    CHECK(r.at("class") == "ice");
    CHECK(std::stod(r.at("mu_hat")) == Approx(0.1).margin(0.05));
  }
  CHECK(readCsv(dir.path / "out" / "slip-sources.csv").size() == 4 * 2);  // sources x filters
}

TEST_CASE("study contact/slip: an unknown filter or contact source is a usage error", "[cli]") {
  Folder dir("study_usage");
  const std::string output = (dir.path / "output.txt").string();
  CHECK(legkit::test::spawnAndWait({LEGKIT_EXE, "study", "contact", "--filter", "no-such-filter",
                                    "--no-plots", "--out", "out"},
                                   dir.path.string(), output) == 1);
  CHECK(legkit::test::spawnAndWait({LEGKIT_EXE, "study", "contact", "--scenarios", "physics-moon"},
                                   dir.path.string(), (dir.path / "o3.txt").string()) == 1);
  CHECK(legkit::test::spawnAndWait({LEGKIT_EXE, "study", "slip", "--filters", "eskf,kalman"},
                                   dir.path.string(), (dir.path / "o4.txt").string()) == 1);
  CHECK(legkit::test::spawnAndWait({LEGKIT_EXE, "study", "slip", "--contact", "no-such-detector",
                                    "--no-plots", "--out", "out"},
                                   dir.path.string(), output) == 1);
  CHECK(slurp(output).find("--contact") != std::string::npos);
}
