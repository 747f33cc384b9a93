// Issue 23 item 7 (and the manager's side of items 5, 6 and 10): legkit-estimate keeps the contract
// of `legkit run --log`. A log run refuses is refused with the same message (exit 2, naming the
// file and line, or the settings' key); a row the filter cannot take fails the run at that line
// (exit 3, as run's FAILED line, without the estimator's class); the robot and the contact source
// are checked against the log's columns; every option checks its range and names itself (exit 1).
// Each case failed before: a run went on (exit 0, or 3 with a 33 m error), or the error named a
// function and no line.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "legkit_cli.hpp"
#include "scratch_folder.hpp"
#include "spawn.hpp"

namespace fs = std::filesystem;

namespace {

using Catch::Matchers::Contains;
using legkit::test::ProgramResult;

ProgramResult estimate(const fs::path& dir, std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), LEGKIT_ESTIMATE_EXE);
  return legkit::test::runProgram(dir, arguments);
}

// The first line of `output` that starts with `prefix`, less the prefix ("" when none does).
std::string lineAfter(const std::string& output, const std::string& prefix) {
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(prefix, 0) == 0) return line.substr(prefix.size());
  }
  return "";
}

// A log as its comment lines, header and rows of fields, to spoil one thing at a time.
struct Csv {
  std::vector<std::string> comments;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  static std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> fields;
    std::istringstream in(line);
    for (std::string f; std::getline(in, f, ',');) fields.push_back(f);
    return fields;
  }
  explicit Csv(const fs::path& path) {
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) {
      if (line.empty()) continue;
      if (line[0] == '#') {
        comments.push_back(line);
      } else if (header.empty()) {
        header = split(line);
      } else {
        rows.push_back(split(line));
      }
    }
  }
  std::size_t col(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return i;
    }
    FAIL("no column " << name);
    return 0;
  }
  double t(std::size_t row) const { return std::stod(rows[row][col("t")]); }
  void setT(std::size_t row, double t) {
    std::ostringstream os;
    os.precision(17);
    os << t;
    rows[row][col("t")] = os.str();
  }
  void dropColumns(const std::string& prefix) {
    std::vector<std::size_t> keep;
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i].rfind(prefix, 0) != 0) keep.push_back(i);
    }
    const auto pick = [&](const std::vector<std::string>& v) {
      std::vector<std::string> out;
      for (const std::size_t i : keep) out.push_back(v[i]);
      return out;
    };
    header = pick(header);
    for (auto& r : rows) r = pick(r);
  }
  void write(const fs::path& path) const {
    std::ofstream out(path, std::ios::binary);
    for (const auto& c : comments) out << c << '\n';
    const auto line = [&](const std::vector<std::string>& v) {
      for (std::size_t i = 0; i < v.size(); ++i) out << (i ? "," : "") << v[i];
      out << '\n';
    };
    line(header);
    for (const auto& r : rows) line(r);
  }
  // The 1-based file line of data row k.
  int lineOf(std::size_t k) const { return static_cast<int>(comments.size() + 2 + k); }
};

// A 1 s simulated trot (1000 rows, the quadruped's joints, forces, contact flags and truth),
// made once for every test case.
const fs::path& baseLog() {
  static const legkit::test::ScratchFolder dir("legkit_estimate_base");
  static const fs::path path = [] {
    const fs::path p = dir.path / "base.csv";
    std::string output;
    const int status =
        legkit::test::runLegkit(dir.path, {"sim", "--duration", "1", "--out", p.string()}, output);
    INFO(output);
    REQUIRE(status == 0);
    return p;
  }();
  return path;
}

// legkit-estimate and `legkit run --log` on the same log: both exit `status`, and the manager's
// message is run's (after each program's name).
void sameAsRun(const fs::path& dir, const std::string& log, int status, const std::string& what) {
  const ProgramResult manager = estimate(dir, {log});
  ProgramResult run = legkit::test::runLegkit(
      dir, {"run", "--log", log, "--no-plots", "--out", (dir / "run-out").string()});
  INFO(manager.output);
  INFO(run.output);
  CHECK(manager.status == status);
  CHECK(run.status == status);
  CHECK_THAT(manager.output, Contains(what));
  const std::string said = lineAfter(manager.output, "legkit-estimate: ");
  CHECK(said == lineAfter(run.output, "legkit: "));
  CHECK_THAT(manager.output, !Contains("::") && !Contains("legkit run --"));
}

}  // namespace

TEST_CASE("legkit-estimate refuses the logs legkit run refuses, with run's message",
          "[cli][issue23][57.11]") {
  const legkit::test::ScratchFolder dir("legkit_estimate_time_base");
  const Csv base(baseLog());
  REQUIRE(base.rows.size() == 1000);

  Csv one = base;
  one.rows.resize(1);
  one.write(dir.path / "one-row.csv");
  sameAsRun(dir.path, "one-row.csv", 2, "one-row.csv: 1 row(s): a run needs at least two");

  Csv tiny = base;
  for (std::size_t k = 0; k < tiny.rows.size(); ++k) tiny.setT(k, 1e-12 * static_cast<double>(k));
  tiny.write(dir.path / "steps-1e-12.csv");
  sameAsRun(dir.path, "steps-1e-12.csv", 2,
            "steps-1e-12.csv: the median time between samples is 1e-12 s");

  Csv repeated = base;
  repeated.setT(500, repeated.t(499));
  repeated.write(dir.path / "repeated.csv");
  sameAsRun(dir.path, "repeated.csv", 2,
            "repeated.csv:" + std::to_string(base.lineOf(500)) +
                ": column 't': timestamps must strictly increase");

  // A 10 s gap: refused naming the line and the option that allows it (the manager's own).
  Csv gap = base;
  for (std::size_t k = 500; k < gap.rows.size(); ++k) gap.setT(k, gap.t(k) + 10.0);
  gap.write(dir.path / "gap.csv");
  sameAsRun(dir.path, "gap.csv", 2,
            "gap.csv:" + std::to_string(base.lineOf(500)) +
                ": a gap of 10.001 s after t = 0.499 s, more than 0.01 s (10 median sample "
                "periods; --max-gap sets another bound)");
  const ProgramResult allowed = estimate(dir.path, {"gap.csv", "--max-gap", "20"});
  INFO(allowed.output);
  CHECK(allowed.status == 0);
  CHECK_THAT(allowed.output, Contains("health: 1 faults (1 time gap)"));
}

TEST_CASE("legkit-estimate fails a run at the log line its filter cannot take, as legkit run",
          "[cli][issue23][57.11]") {
  const legkit::test::ScratchFolder dir("legkit_estimate_failure");
  Csv log(baseLog());
  // Finite (the reader takes it), but the leg's kinematics overflow: the filter refuses the foot.
  log.rows[500][log.col("dq_FL_1")] = "1.7e308";
  log.rows[500][log.col("dq_FL_2")] = "1.7e308";
  log.write(dir.path / "overflow.csv");
  const std::string failed =
      "FAILED invariant-ekf: overflow.csv:" + std::to_string(log.lineOf(500)) +
      ", t = 0.5 s (row 500): threw: foot id 0 p_body is not finite";
  const ProgramResult manager = estimate(dir.path, {"overflow.csv"});
  const ProgramResult run = legkit::test::runLegkit(
      dir.path, {"run", "--log", "overflow.csv", "--no-plots", "--out", "run-out"});
  INFO(manager.output);
  INFO(run.output);
  CHECK(manager.status == 3);
  CHECK(run.status == 3);
  CHECK_THAT(manager.output, Contains(failed));
  CHECK_THAT(run.output, Contains(failed));
  CHECK_THAT(manager.output + run.output, !Contains("::step"));
}

TEST_CASE("legkit-estimate checks the robot and the contact source against the log's columns",
          "[cli][issue23][57.11]") {
  const legkit::test::ScratchFolder dir("legkit_estimate_columns");
  Csv log(baseLog());
  log.dropColumns("contact_");
  log.write(dir.path / "no-flags.csv");
  ProgramResult r = estimate(dir.path, {"no-flags.csv", "--contact", "truth"});
  INFO(r.output);
  CHECK(r.status == 1);  // was 0: no foot ever in contact, 0.136 m
  CHECK_THAT(r.output, Contains("legkit-estimate: --contact truth: no-flags.csv has no contact "
                                "columns; choose a detector"));

  r = estimate(dir.path, {"no-flags.csv", "--contact", "gait-clock"});
  INFO(r.output);
  CHECK(r.status == 1);
  CHECK_THAT(r.output, Contains("--contact gait-clock: contact detector gait-clock needs a gait "
                                "schedule: give the robot's planned gait in the settings, "
                                "contact.gait"));
  // With the settings' planned gait it runs, as `legkit run --config` does.
  legkit::test::writeFile(dir.path / "gait.yaml",
                          "contact:\n  detector: gait-clock\n  gait:\n    period: 0.5\n"
                          "    duty: 0.6\n    offsets: [0, 0.5, 0.5, 0]\n");
  r = estimate(dir.path, {"no-flags.csv", "--config", "gait.yaml"});
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Contains("on contacts from gait-clock"));

  // The iCub's settings on the quadruped's joint columns: refused naming the key (was exit 3
  // after a run through the wrong legs, a position error of 33 m).
  const std::string icub = LEGKIT_SOURCE_DIR "/config/robots/icub.yaml";
  r = estimate(dir.path, {"no-flags.csv", "--config", icub});
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains(icub + ": robot.model: no-flags.csv has no generic joint columns "
                                       "(joint<k>_q) for the robot's legs"));

  // Limits that reject most of the log: a void run (exit 3) with the counts.
  legkit::test::writeFile(dir.path / "limits.yaml", "limits:\n  gyro_max: 0.1\n");
  r = estimate(dir.path, {"no-flags.csv", "--config", "limits.yaml"});
  INFO(r.output);
  CHECK(r.status == 3);
  CHECK_THAT(r.output, Contains("VOID invariant-ekf: "));
  CHECK_THAT(r.output, Contains(" samples' input rejected (more than 5.000 %)"));
}

TEST_CASE("every option of legkit-estimate checks its range and names itself",
          "[cli][issue23][57.11]") {
  const legkit::test::ScratchFolder dir("legkit_estimate_options");
  const std::string base = baseLog().string();
  struct Case {
    std::vector<std::string> arguments;
    std::string said;
  };
  const std::vector<Case> cases = {
      {{"--init", "nan"}, "--init: must be a finite number in [0, 60], got 'nan'"},
      {{"--init", "1e308"}, "--init: must be a finite number in [0, 60]"},
      {{"--init", "0.001"}, "--init: must be 0 (off) or in [0.01, 60], got 0.001"},
      {{"--init", ""}, "--init: must be a finite number in [0, 60], got ''"},
      {{"--init-wait", "nan"}, "--init-wait: must be a finite number in [0, 3600]"},
      {{"--init-wait", "1e308"}, "--init-wait: must be a finite number in [0, 3600]"},
      {{"--mpc-rate", "0"}, "--mpc-rate: must be a finite number in [1, 10000]"},
      {{"--mpc-rate", "1e-300"}, "--mpc-rate: must be a finite number in [1, 10000]"},
      {{"--mpc-rate", "inf"}, "--mpc-rate: must be a finite number in [1, 10000]"},
      {{"--mpc-latency", "nan"}, "--mpc-latency: must be a finite number in [0, 1]"},
      {{"--mpc-latency", "1e308"}, "--mpc-latency: must be a finite number in [0, 1]"},
      {{"--settle", "nan"}, "--settle: must be a finite number in [0, 1]"},
      {{"--max-gap", "nan"}, "--max-gap: must be a finite number in [1e-06, 3600]"},
      {{"--estimator", ""}, "--estimator:  not in {"},
      {{"--estimator", "bogus"}, "--estimator: bogus not in {"},
      {{"--contact", ""}, "--contact:  not in {truth,"},
      {{"--config", ""}, "--config: must not be empty"},
      {{"--out", ""}, "--out: must not be empty"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> arguments = {base};
    arguments.insert(arguments.end(), c.arguments.begin(), c.arguments.end());
    const ProgramResult r = estimate(dir.path, arguments);
    INFO(c.arguments.front() << " '" << c.arguments.back() << "': " << r.output);
    CHECK(r.status == 1);
    CHECK_THAT(r.output, Contains(c.said));
  }
  const ProgramResult r = estimate(dir.path, {""});
  INFO(r.output);
  CHECK(r.status == 1);
  CHECK_THAT(r.output, Contains("log: must not be empty"));
}

TEST_CASE("legkit-estimate whose report cannot be written is not done", "[cli][issue23][57.11]") {
  const legkit::test::ScratchFolder dir("legkit_estimate_full");
  const std::string base = baseLog().string();
  // Standard output on a full disk (was exit 0 with nothing written).
  CHECK(legkit::test::spawnAndWait({LEGKIT_ESTIMATE_EXE, base}, dir.path.string(), "/dev/full") ==
        2);
  const ProgramResult r = estimate(dir.path, {base, "--out", "/dev/full"});
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("cannot write /dev/full (--out)"));
}
