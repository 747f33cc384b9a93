// The physics studies' shards (tools/legkit/contact_report.hpp, faults_report.hpp): their rows
// read back bit for bit (NaN, infinities, the smallest numbers), the report made from the read
// rows is the report made from the rows (stdout and every file), and a truncated or mismatched
// rows file is refused naming it.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "contact_report.hpp"
#include "faults_report.hpp"
#include "output.hpp"
#include "scratch_folder.hpp"
#include "shard.hpp"

using namespace legkit;
using namespace legkit::tools;
namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Awkward numbers: each needs all 17 digits, or is special.
double odd(int i) {
  const double values[] = {1.0 / 3.0, 0.1 + 0.2, -2.0 / 7.0, 4.9e-324, 1e308, kNaN, kInf, 0.0};
  return values[i % 8] * (i / 8 + 1);
}

std::string slurpFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeFile(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// The first `lines` lines of `text`.
std::string head(const std::string& text, int lines) {
  std::size_t at = 0;
  for (int i = 0; i < lines; ++i) at = text.find('\n', at) + 1;
  return text.substr(0, at);
}

ContactRows contactRows() {
  ContactRows rows;
  rows.detectors = {"schmitt", "probabilistic"};
  int k = 0;
  for (const char* name : {"physics-stand", "physics-trot"}) {
    ContactScenario s;
    s.run = {name, k > 0, odd(k)};
    for (std::size_t d = 0; d < rows.detectors.size(); ++d) {
      ContactDetectorRow r;
      r.scores = {odd(k + 1), odd(k + 2), odd(k + 3), odd(k + 4), kNaN, odd(k + 6), odd(k + 7),
                  odd(k + 8), 3,          4,          1,          0,    2};
      r.undecided_percent = odd(k + 9);
      r.position_rmse = odd(k + 10);
      r.velocity_rmse = odd(k + 11);
      s.rows.push_back(r);
      ++k;
    }
    s.traced = std::string(name) == "physics-trot";
    if (s.traced) {
      s.trace_detected.resize(rows.detectors.size());
      for (int j = 0; j < 5; ++j) {
        s.trace_t.push_back(odd(j));
        s.trace_force.push_back(odd(j + 1));
        s.trace_fn.push_back(odd(j + 2));
        s.trace_truth.push_back(j % 2);
        for (auto& c : s.trace_detected) c.push_back((j + 1) % 2);
      }
    }
    rows.scenarios.push_back(s);
  }
  return rows;
}

SlipRows slipRows(bool sources) {
  SlipRows rows;
  rows.filters = {"eskf", "invariant-ekf"};
  rows.reactions = {"none", "inflate"};
  int k = 0;
  for (const char* name : {"physics-ice", "physics-trot"}) {
    SlipScenario s;
    s.run = {name, false, 0.0};
    s.friction = {odd(k), 0.05};
    for (const std::string& f : rows.filters) {
      for (const std::string& r : rows.reactions) {
        s.runs.push_back({f, r, odd(k), odd(k + 1), {k, k / 2, odd(k + 2), kNaN, odd(k + 3), 0.0}});
        ++k;
      }
    }
    s.terrain = SlipTerrain{"slippery", odd(k), odd(k + 1), 7, odd(k + 2), odd(k + 3)};
    s.traced = std::string(name) == "physics-ice";
    if (s.traced) {
      s.threshold = 7.8147279032511765;
      for (int j = 0; j < 4; ++j) s.trace.push_back({odd(j), 0.05, odd(j + 1), kNaN, j == 2});
    }
    rows.scenarios.push_back(s);
  }
  if (sources) {
    SlipSources s;
    s.duration = 10.0;
    s.sources = {"truth", "schmitt"};
    s.rmse = {{{odd(1), odd(2)}, {odd(3), odd(4)}}, {{odd(5), odd(6)}, {odd(7), odd(8)}}};
    rows.sources = s;
  }
  return rows;
}

}  // namespace

TEST_CASE("study contact's rows read back bit for bit, and make the same report", "[shard]") {
  test::ScratchFolder dir("physics_shard_contact");
  const ContactRows rows = contactRows();
  std::ostringstream written;
  writeContactRows(written, rows);
  writeFile(dir.path / "rows.csv", written.str());
  const ContactRows read =
      readContactRows(dir.path / "rows.csv", {"physics-stand", "physics-trot"});
  std::ostringstream again;
  writeContactRows(again, read);
  CHECK(again.str() == written.str());

  const ContactHeading heading{3, 2.5, "invariant-ekf", 40.0, 20.0};
  fs::create_directories(dir.path / "a");
  fs::create_directories(dir.path / "b");
  std::ostringstream a, b;
  reportContact(a, dir.path / "a", heading, rows);
  reportContact(b, dir.path / "b", heading, read);
  CHECK(a.str().substr(0, a.str().find("tables:")) == b.str().substr(0, b.str().find("tables:")));
  for (const char* file : {"contact.csv", "contact-trace.csv"}) {
    CHECK(slurpFile(dir.path / "a" / file) == slurpFile(dir.path / "b" / file));
  }

  // Merged from two shards: the same as whole.
  std::ostringstream first, second;
  writeContactRows(first, ContactRows{rows.detectors, {rows.scenarios[0]}});
  writeContactRows(second, ContactRows{rows.detectors, {rows.scenarios[1]}});
  writeFile(dir.path / "1.csv", first.str());
  writeFile(dir.path / "2.csv", second.str());
  ContactRows all;
  appendContactRows(all, readContactRows(dir.path / "1.csv", {"physics-stand"}), "1");
  appendContactRows(all, readContactRows(dir.path / "2.csv", {"physics-trot"}), "2");
  std::ostringstream merged;
  writeContactRows(merged, all);
  CHECK(merged.str() == written.str());

  // Truncated at every line, or another scenario than the block's: refused naming the file.
  const std::string text = written.str();  // (str() is a copy)
  const int lines = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  for (int n = 0; n < lines; ++n) {
    INFO(n);
    writeFile(dir.path / "cut.csv", head(text, n));
    CHECK_THROWS_WITH(readContactRows(dir.path / "cut.csv", {"physics-stand", "physics-trot"}),
                      Catch::Contains("cut.csv"));
  }
  CHECK_THROWS_WITH(readContactRows(dir.path / "rows.csv", {"physics-stand", "physics-push"}),
                    Catch::Contains("'physics-trot' where 'physics-push' was expected"));
}

TEST_CASE("study slip's rows read back bit for bit, and make the same report", "[shard]") {
  test::ScratchFolder dir("physics_shard_slip");
  const SlipRows rows = slipRows(true);
  std::ostringstream written;
  writeSlipRows(written, rows);
  writeFile(dir.path / "rows.csv", written.str());
  const std::vector<std::string> names = {"physics-ice", "physics-trot"};
  const SlipRows read = readSlipRows(dir.path / "rows.csv", names, true);
  std::ostringstream again;
  writeSlipRows(again, read);
  CHECK(again.str() == written.str());

  const SlipHeading heading{5, 1.5, "fallback"};
  fs::create_directories(dir.path / "a");
  fs::create_directories(dir.path / "b");
  std::ostringstream a, b;
  reportSlip(a, dir.path / "a", heading, rows);
  reportSlip(b, dir.path / "b", heading, read);
  CHECK(a.str().substr(0, a.str().find("tables:")) == b.str().substr(0, b.str().find("tables:")));
  for (const char* file : {"slip.csv", "slip-sources.csv", "slip-terrain.csv", "slip-trace.csv"}) {
    CHECK(slurpFile(dir.path / "a" / file) == slurpFile(dir.path / "b" / file));
  }

  // A shard of the scenarios only, and one of the sources only.
  SlipRows scenarios_only = rows;
  scenarios_only.sources.reset();
  SlipRows sources_only = rows;
  sources_only.scenarios.clear();
  std::ostringstream first, second;
  writeSlipRows(first, scenarios_only);
  writeSlipRows(second, sources_only);
  writeFile(dir.path / "1.csv", first.str());
  writeFile(dir.path / "2.csv", second.str());
  SlipRows all;
  appendSlipRows(all, readSlipRows(dir.path / "1.csv", names, false), "1");
  appendSlipRows(all, readSlipRows(dir.path / "2.csv", {}, true), "2");
  std::ostringstream merged;
  writeSlipRows(merged, all);
  CHECK(merged.str() == written.str());
  CHECK_THROWS_WITH(readSlipRows(dir.path / "1.csv", names, true), Catch::Contains("1.csv"));

  const std::string text = written.str();  // (str() is a copy)
  const int lines = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  for (int n = 0; n < lines; ++n) {
    INFO(n);
    writeFile(dir.path / "cut.csv", head(text, n));
    CHECK_THROWS_WITH(readSlipRows(dir.path / "cut.csv", names, true), Catch::Contains("cut.csv"));
  }
}

TEST_CASE("study faults' rows read back bit for bit, and make the same table", "[shard]") {
  std::vector<FaultCaseResult> rows(2);
  rows[0].name = "none";
  rows[0].answered = {{}, odd(0), odd(1), odd(2), odd(3), true, ""};
  rows[1].name = "FR knee encoder frozen from 1.5 s";
  rows[1].answered = {
      {{"stuck encoder", 1.6}, {"IMU dropout", odd(1)}}, odd(4), kNaN, odd(6), 4.9e-324, false,
      "1 no contact, for longer than the bound"};
  rows[1].without = FaultRun{{}, odd(9), odd(10), odd(11), odd(12), true, ""};
  const nlohmann::json json = nlohmann::json::parse(faultRowsToJson(rows).dump(2));
  const std::vector<FaultCaseResult> read = faultRowsFromJson(json, "shard.json");
  CHECK(faultRowsToJson(read) == faultRowsToJson(rows));
  std::ostringstream a, b;
  reportFaults(a, {"eskf", 3.0, 7}, rows);
  reportFaults(b, {"eskf", 3.0, 7}, read);
  CHECK(a.str() == b.str());
  CHECK_THROWS_WITH(faultRowsFromJson(nlohmann::json::object(), "x/shard.json"),
                    Catch::Contains("x/shard.json"));
  nlohmann::json broken = json;
  broken[1]["answered"]["maxima"][0] = "1.0x";
  CHECK_THROWS_WITH(faultRowsFromJson(broken, "y/shard.json"), Catch::Contains("y/shard.json"));
}
