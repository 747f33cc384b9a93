// The legkit command line as a user meets it: exit codes, --version, outputs written atomically
// with summary.json last, no shell between it and the plot scripts, plots for recorded logs, the
// TUM files of --tum.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/log_reader.hpp"
#include "io/log_writer.hpp"
#include "legkit_cli.hpp"
#include "sim/simulator.hpp"
#include "spawn.hpp"

namespace fs = std::filesystem;

namespace {

using Folder = legkit::test::ScratchFolder;
using legkit::test::slurp;

using Result = legkit::test::ProgramResult;

using legkit::test::runLegkit;

}  // namespace

TEST_CASE("cli: --version, --help and a wrong command line", "[cli]") {
  const Folder dir("cli_usage");
  Result r = runLegkit(dir.path, {"--version"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("legkit " LEGKIT_VERSION));
  r = runLegkit(dir.path, {"--help"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("Exit codes"));
  CHECK(runLegkit(dir.path, {"run", "--no-such-option"}).status == 1);
  CHECK(runLegkit(dir.path, {"run", "--scenario", "no-such-scenario"}).status == 1);
  CHECK(runLegkit(dir.path, {"sim", "--slip-foot", "XX", "--out", "log.csv"}).status == 1);
  CHECK(runLegkit(dir.path, {"sim", "--dropout", "1", "--out", "log.csv"}).status == 1);
  CHECK_FALSE(fs::exists(dir.path / "log.csv"));
  // A log that cannot be read is an input error, with the reader's message.
  r = runLegkit(dir.path, {"run", "--log", "no-such-file.csv"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Matchers::Contains("no-such-file.csv"));
}

TEST_CASE("cli: a bad log is refused with its file and line, unchanged", "[cli]") {
  const Folder dir("cli_badlog");
  legkit::sim::SimOptions options;
  options.duration = 0.2;
  std::ostringstream text;
  legkit::io::writeLog(text, legkit::sim::simulate(options).log);
  // The second data row's time becomes a word.
  std::istringstream lines(text.str());
  std::ofstream bad(dir.path / "bad.csv");
  int line_number = 0, data_rows = 0, spoiled = 0;
  for (std::string line; std::getline(lines, line);) {
    ++line_number;
    if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0])) && ++data_rows == 2) {
      line = "zero" + line.substr(line.find(','));
      spoiled = line_number;
    }
    bad << line << '\n';
  }
  bad.close();
  REQUIRE(spoiled > 0);
  const Result r = runLegkit(dir.path, {"run", "--log", "bad.csv", "--out", "out", "--no-plots"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output,
             Catch::Matchers::StartsWith("legkit: bad.csv:" + std::to_string(spoiled) + ": "));
  CHECK_FALSE(fs::exists(dir.path / "out"));
}

TEST_CASE("cli: the time base of a recorded log is checked", "[cli]") {
  const Folder dir("cli_timebase");
  legkit::sim::SimOptions options;
  options.duration = 2.0;
  options.faults.dropouts = {{1.0, 0.5}};  // no samples for 0.5 s: a gap of 500 periods
  legkit::io::Log log = legkit::sim::simulate(options).log;
  legkit::io::writeLog((dir.path / "gap.csv").string(), log);
  for (legkit::io::LogRow& row : log.rows) row.t *= 1000.0;  // milliseconds
  legkit::io::writeLog((dir.path / "ms.csv").string(), log);

  Result r = runLegkit(dir.path, {"run", "--log", "ms.csv", "--no-plots", "--out", "out"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Matchers::Contains("ms.csv"));
  CHECK_THAT(r.output, Catch::Matchers::Contains("in seconds?"));
  CHECK_FALSE(fs::exists(dir.path / "out"));

  r = runLegkit(dir.path, {"run", "--log", "gap.csv", "--no-plots", "--out", "out"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Matchers::Contains("gap.csv:"));
  CHECK_THAT(r.output, Catch::Matchers::Contains("a gap of 0.50"));
  CHECK_FALSE(fs::exists(dir.path / "out" / "summary.json"));

  // Allowed with --max-gap: the estimators reject the gap themselves, and the table says so.
  r = runLegkit(dir.path,
                {"run", "--log", "gap.csv", "--no-plots", "--out", "out", "--max-gap", "1"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("health of eskf: 1 time gap"));
  CHECK(fs::exists(dir.path / "out" / "summary.json"));
}

TEST_CASE("cli: a study makes its output folder before its runs", "[cli]") {
  const Folder dir("cli_study");
  std::ofstream(dir.path / "a-file") << "x\n";
  const Result r = runLegkit(
      dir.path, {"study", "consistency", "--runs", "1", "--duration", "0.5", "--out", "a-file"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Matchers::Contains("a-file"));
  CHECK_THAT(r.output, !Catch::Matchers::Contains("ANEES"));
}

TEST_CASE(
    "cli: a finished run ends with summary.json; the previous run's outputs are gone, the user's "
    "files stay",
    "[cli]") {
  const Folder dir("cli_summary");
  const fs::path out = dir.path / "out";
  fs::create_directories(out);
  std::ofstream(out / "estimate_mine.csv") << "mine\n";
  std::ofstream(out / "notes.png") << "mine\n";
  std::ofstream(dir.path / "eskf-only.yaml") << "estimators: [\"eskf\"]\n";
  Result r = runLegkit(dir.path, {"run", "--duration", "2", "--no-plots", "--out", "out"});
  REQUIRE(r.status == 0);
  CHECK(fs::exists(out / "estimate_invariant-ekf.csv"));
  r = runLegkit(dir.path, {"run", "--duration", "2", "--no-plots", "--config", "eskf-only.yaml",
                           "--out", "out"});
  REQUIRE(r.status == 0);
  CHECK_FALSE(fs::exists(out / "estimate_invariant-ekf.csv"));  // the previous run's
  CHECK(slurp(out / "estimate_mine.csv") == "mine\n");
  CHECK(slurp(out / "notes.png") == "mine\n");
  CHECK_THAT(slurp(out / "summary.json"),
             Catch::Matchers::Contains("\"estimate_eskf.csv\"") &&
                 !Catch::Matchers::Contains("\"estimate_invariant-ekf.csv\""));
  // A summary.json that is not the kit's: an error, nothing removed.
  std::ofstream(out / "summary.json") << "stale\n";
  r = runLegkit(dir.path, {"run", "--duration", "2", "--no-plots", "--out", "out"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Matchers::Contains("is not a legkit run's"));
  CHECK(fs::exists(out / "estimate_eskf.csv"));
  fs::remove(out / "summary.json");
  r = runLegkit(dir.path, {"run", "--duration", "2", "--no-plots", "--out", "out"});
  REQUIRE(r.status == 0);
  const std::string summary = slurp(out / "summary.json");
  CHECK_THAT(summary, Catch::Matchers::Contains("\"exit_status\": 0"));
  CHECK_THAT(summary, Catch::Matchers::Contains("\"invariant-ekf\""));
  CHECK_THAT(summary, Catch::Matchers::Contains("\"legkit_version\": \"" LEGKIT_VERSION));
  CHECK_THAT(summary, Catch::Matchers::Contains("--out out"));
  for (const fs::directory_entry& e : fs::directory_iterator(out)) {
    CHECK(e.path().extension() != ".tmp");
  }
}

TEST_CASE("cli: a write that fails is an error, and nothing claims it was written", "[cli]") {
  const Folder dir("cli_full");
  const fs::path out = dir.path / "out";
  fs::create_directories(out);
  // The estimates of one filter would go through a link (to a full disk): refused.
  fs::create_symlink("/dev/full", out / "estimate_eskf.csv.tmp");
  Result r = runLegkit(dir.path, {"run", "--duration", "2", "--no-plots", "--out", "out"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Matchers::Contains("cannot write out/estimate_eskf.csv"));
  CHECK_THAT(r.output, !Catch::Matchers::Contains("wrote"));
  CHECK_FALSE(fs::exists(out / "summary.json"));
  // An output folder that is a file.
  std::ofstream(dir.path / "a-file") << "x\n";
  r = runLegkit(dir.path, {"run", "--duration", "2", "--no-plots", "--out", "a-file"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Matchers::Contains("a-file"));
  // legkit sim to a full disk.
  fs::create_symlink("/dev/full", dir.path / "log.csv.tmp");
  r = runLegkit(dir.path, {"sim", "--duration", "1", "--out", "log.csv"});
  CHECK(r.status == 2);
  CHECK_FALSE(fs::exists(dir.path / "log.csv"));
}

TEST_CASE("cli: the plot script gets its arguments without a shell", "[cli]") {
  const Folder dir("cli_inject");
  const Result r =
      runLegkit(dir.path, {"run", "--duration", "2", "--out", "x'; touch INJECTED; echo '"});
  CHECK(r.status == 0);
  CHECK_FALSE(fs::exists(dir.path / "INJECTED"));
  CHECK(fs::exists(dir.path / "x'; touch INJECTED; echo '" / "trajectory-top.png"));
}

TEST_CASE("cli: a log of one row is an input error, not a table of zeros", "[cli]") {
  const Folder dir("cli_one_row");
  legkit::sim::SimOptions options;
  options.duration = 0.1;
  legkit::io::Log log = legkit::sim::simulate(options).log;
  log.rows.resize(1);
  legkit::io::writeLog((dir.path / "one.csv").string(), log);
  const Result r = runLegkit(dir.path, {"run", "--log", "one.csv", "--no-plots", "--out", "out"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Matchers::Contains("one.csv: 1 row(s): a run needs at least two"));
  CHECK_THAT(r.output, !Catch::Matchers::Contains("ANEES"));
  CHECK_FALSE(fs::exists(dir.path / "out" / "summary.json"));
}

TEST_CASE("cli: a recorded log without ground truth gets its plots too", "[cli]") {
  const Folder dir("cli_recorded");
  legkit::sim::SimOptions options;
  options.duration = 2.0;
  options.ground_truth = false;
  legkit::io::writeLog((dir.path / "robot.csv").string(), legkit::sim::simulate(options).log);
  const Result r = runLegkit(dir.path, {"run", "--log", "robot.csv", "--out", "out"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("plots"));
  CHECK(fs::exists(dir.path / "out" / "trajectory-top.png"));
  CHECK(fs::exists(dir.path / "out" / "sigma.png"));
}

TEST_CASE("cli: a run whose filters had to recover exits 3 and says which", "[cli]") {
  const Folder dir("cli_recover");
  legkit::sim::SimOptions options;
  options.duration = 1.0;
  options.foot_columns = legkit::io::FootCovariance::kDiagonal;
  legkit::io::Log log = legkit::sim::simulate(options).log;
  // A foot claimed exact to 1e-15 m: the filters' covariances cannot keep their digits.
  for (legkit::io::LogRow& row : log.rows) row.feet[0].cov = 1e-30 * Eigen::Matrix3d::Identity();
  legkit::io::writeLog((dir.path / "exact-foot.csv").string(), log);
  const Result r =
      runLegkit(dir.path, {"run", "--log", "exact-foot.csv", "--no-plots", "--out", "out"});
  CHECK(r.status == 3);
  CHECK_THAT(r.output, Catch::Matchers::Contains("state unhealthy (recovered)"));
  CHECK_THAT(r.output, Catch::Matchers::Contains("health of eskf: "));
  CHECK_THAT(slurp(dir.path / "out" / "summary.json"),
             Catch::Matchers::Contains("\"exit_status\": 3"));
}

TEST_CASE("cli: a run whose estimator could not use its input is void: exit 3 with the counts",
          "[cli]") {
  const Folder dir("cli_void");
  // A gyro range of 0.1 rad/s: the trot's turning rates are beyond it on most samples.
  std::ofstream(dir.path / "narrow.yaml") << "estimators: [eskf]\nlimits:\n  gyro_max: 0.1\n";
  Result r = runLegkit(dir.path, {"run", "--scenario", "trot", "--duration", "2", "--no-plots",
                                  "--config", "narrow.yaml", "--out", "out"});
  CHECK(r.status == 3);
  CHECK_THAT(r.output, Catch::Matchers::Contains("VOID eskf: ") &&
                           Catch::Matchers::Contains(" of 2000 samples' input rejected"));
  CHECK_THAT(slurp(dir.path / "out" / "summary.json"),
             Catch::Matchers::Contains("\"healthy\": false"));
  // The kit's own limits on the same log reject nothing: exit 0.
  std::ofstream(dir.path / "wide.yaml") << "estimators: [eskf]\n";
  r = runLegkit(dir.path, {"run", "--scenario", "trot", "--duration", "2", "--no-plots", "--config",
                           "wide.yaml", "--out", "out"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, !Catch::Matchers::Contains("VOID"));
}

namespace {

// Data rows of a CSV file (lines that are neither comments nor its header).
int dataRows(const fs::path& path) {
  std::ifstream f(path);
  int rows = 0;
  for (std::string line; std::getline(f, line);) rows += !line.empty() && line[0] != '#';
  return rows - 1;
}

}  // namespace

TEST_CASE("cli: --estimate-rate thins the estimate files, never the metrics", "[cli]") {
  const Folder dir("cli_rate");
  // 2 s at 1 kHz: 2000 rows in the log, t = 0 .. 1.999.
  Result r = runLegkit(dir.path, {"run", "--duration", "2", "--no-plots", "--out", "thin"});
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("estimates at 100 Hz"));
  r = runLegkit(dir.path, {"run", "--duration", "2", "--no-plots", "--out", "all",
                           "--estimate-rate", "all", "--json"});
  REQUIRE(r.status == 0);
  const int log_rows = dataRows(dir.path / "all" / "log.csv");
  CHECK(log_rows == 2000);
  for (const char* name : {"eskf", "imu-dead-reckoning", "linear-kf"}) {
    const std::string file = std::string("estimate_") + name + ".csv";
    CHECK(dataRows(dir.path / "all" / file) == log_rows);
    CHECK(dataRows(dir.path / "thin" / file) == 201);  // t = 0, 0.01, .. 1.99 and 1.999
  }
  // The metrics come from every sample, whatever the files keep (us_per_step is wall time).
  const auto metrics = [](const std::string& summary) {
    std::istringstream lines(summary);
    std::string kept;
    for (std::string line; std::getline(lines, line);) {
      if (line.find("rmse") != std::string::npos || line.find("drift") != std::string::npos)
        kept += line + '\n';
    }
    return kept;
  };
  REQUIRE_THAT(metrics(slurp(dir.path / "all" / "summary.json")),
               Catch::Matchers::Contains("\"position_rmse_m\""));
  CHECK(metrics(slurp(dir.path / "thin" / "summary.json")) ==
        metrics(slurp(dir.path / "all" / "summary.json")));
  CHECK_THAT(slurp(dir.path / "all" / "summary.json"),
             Catch::Matchers::Contains("\"estimate_rate_hz\": \"all\""));

  CHECK(runLegkit(dir.path, {"run", "--estimate-rate", "-1", "--out", "x"}).status == 1);
  CHECK(runLegkit(dir.path, {"run", "--estimate-rate", "fast", "--out", "x"}).status == 1);
  CHECK_FALSE(fs::exists(dir.path / "x"));
  CHECK_THAT(runLegkit(dir.path, {"run", "--help"}).output,
             Catch::Matchers::Contains("--estimate-rate"));
}

TEST_CASE("cli: a study shows its progress, and only outside its results", "[cli]") {
  const Folder dir("cli_progress");
  const Result r = runLegkit(dir.path, {"study", "consistency", "--runs", "3", "--duration", "0.5",
                                        "--threads", "2", "--no-plots", "--out", "out"});
  REQUIRE(r.status == 0);
  INFO(r.output);
  // Not a terminal: plain lines, one per run here, counted in order across both threads, before
  // the table.
  CHECK_THAT(r.output, Catch::Matchers::StartsWith("consistency: run 1/3\nconsistency: run 2/3\n"
                                                   "consistency: run 3/3\nConsistency on"));
  CHECK(r.output.find('\r') == std::string::npos);
  CHECK_THAT(slurp(dir.path / "out" / "consistency.csv"), !Catch::Matchers::Contains("run "));
  // The table gives the end of the run beside the whole (chapter 57.10: the long horizon).
  CHECK_THAT(r.output, Catch::Matchers::Contains("last 10 %"));
  CHECK_THAT(r.output, !Catch::Matchers::Contains("nan"));
}

TEST_CASE("cli: sim --foot-columns says the feet replace the joints, and they do", "[cli]") {
  const Folder dir("cli_feet");
  CHECK_THAT(runLegkit(dir.path, {"sim", "--help"}).output,
             Catch::Matchers::Contains("instead of joint columns"));
  REQUIRE(runLegkit(dir.path,
                    {"sim", "--duration", "0.1", "--foot-columns", "diagonal", "--out", "feet.csv"})
              .status == 0);
  const legkit::io::Log log = legkit::io::readLog((dir.path / "feet.csv").string());
  CHECK(log.layout.foot_columns == legkit::io::FootCovariance::kDiagonal);
  CHECK_FALSE(log.layout.joints);
}

TEST_CASE("cli: sim writes a physics log with the true contacts", "[cli][physics]") {
  const Folder dir("cli_physics");
  CHECK_THAT(runLegkit(dir.path, {"sim", "--help"}).output,
             Catch::Matchers::Contains("physics (MuJoCo"));
  Result r = runLegkit(
      dir.path, {"sim", "--scenario", "physics-stand", "--duration", "0.3", "--out", "s.csv"});
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("physics-stand (physics)"));
  const legkit::io::Log log = legkit::io::readLog((dir.path / "s.csv").string());
  CHECK(log.rows.size() == 300);
  CHECK(log.layout.joints);
  CHECK(log.layout.contact_truth);
  CHECK(log.layout.ground_truth);
  // Standing: every foot down, carrying about a quarter of the weight (15.2 kg).
  double total = 0.0;
  for (int leg = 0; leg < 4; ++leg) {
    CHECK(log.rows.back().gt_feet[leg].contact);
    CHECK(log.rows.back().contact[leg]);
    total += log.rows.back().gt_feet[leg].normal_force;
  }
  CHECK(total == Approx(15.2 * 9.81).epsilon(0.1));
  // The controller on an estimator's estimate instead of the truth.
  r = runLegkit(dir.path, {"sim", "--scenario", "physics-stand", "--duration", "0.3",
                           "--closed-loop", "invariant-ekf", "--out", "c.csv"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("closed loop on invariant-ekf"));
}

TEST_CASE("cli: physics options out of range are usage errors naming the option",
          "[cli][physics]") {
  const Folder dir("cli_physics_usage");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--scenario", "physics-trot", "--friction", "5"}, "--friction"},
      {{"--scenario", "physics-trot", "--friction", "0"}, "--friction"},
      {{"--scenario", "physics-trot", "--push", "80"}, "--push"},
      {{"--scenario", "physics-push", "--push", "1000"}, "--push"},
      {{"--scenario", "physics-push", "--push", "-5"}, "--push"},
      {{"--scenario", "physics-stand", "--duration", "0"}, "--duration"},
      {{"--scenario", "physics-push", "--duration", "2"}, "--duration"},  // the push is at 3 s
      {{"--scenario", "physics-stand", "--duration", "1e6"}, "--duration"},
      {{"--scenario", "physics-stand", "--closed-loop", "kalman"}, "--closed-loop"},
      {{"--scenario", "physics-stand", "--slip-foot", "FR"}, "--slip-foot"},
      {{"--scenario", "physics-stand", "--rate", "1e5"}, "--rate"},
      {{"--scenario", "trot", "--friction", "0.3"}, "--friction"},
      {{"--scenario", "trot", "--closed-loop", "eskf"}, "--closed-loop"},
      {{"--scenario", "physics-nowhere"}, "--scenario"},
  };
  const Result run = runLegkit(dir.path, {"run", "--scenario", "physics-ice-push", "--duration",
                                          "1", "--no-plots", "--out", "out"});
  CHECK(run.status == 1);
  CHECK_THAT(run.output, Catch::Matchers::Contains("--duration: physics-ice-push pushes"));
  for (const auto& [arguments, option] : cases) {
    std::vector<std::string> command = {"sim", "--out", "bad.csv"};
    command.insert(command.end(), arguments.begin(), arguments.end());
    const Result r = runLegkit(dir.path, command);
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK_THAT(r.output, Catch::Matchers::Contains(option));
    CHECK_FALSE(fs::exists(dir.path / "bad.csv"));
  }
}

TEST_CASE("cli: numeric options refuse NaN, inf and absurd values by name", "[cli]") {
  // CLI11's own range checks let NaN through; these once ran on (--max-gap nan: exit 0), fell
  // back to a default (study --runs 0, --duration -1) or failed naming a function, not the option.
  const Folder dir("cli_numeric_options");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"run", "--max-gap", "nan"}, "--max-gap"},
      {{"run", "--max-gap", "-1"}, "--max-gap"},
      {{"run", "--duration", "nan"}, "--duration"},
      {{"run", "--duration", "-1"}, "--duration"},
      {{"run", "--duration", "1e308"}, "--duration"},
      {{"study", "consistency", "--runs", "0"}, "--runs"},
      {{"study", "consistency", "--duration", "nan"}, "--duration"},
      {{"study", "consistency", "--duration", "0"}, "--duration"},
      {{"allan", "--simulate", "nan"}, "--simulate"},
      {{"allan", "--simulate", "1e308"}, "--simulate"},
      {{"allan", "--simulate", "10", "--rate", "inf"}, "--rate"},
      {{"allan", "--simulate", "10", "--ratio", "nan"}, "--ratio"},
  };
  for (const auto& [arguments, option] : cases) {
    std::vector<std::string> command = arguments;
    command.insert(command.end(), {"--out", "out"});
    const Result r = runLegkit(dir.path, command);
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK_THAT(r.output, Catch::Matchers::Contains(option));
    CHECK_FALSE(fs::exists(dir.path / "out"));
  }
}

TEST_CASE("cli: a robot that falls is a failed run with the time and the reason",
          "[cli][physics]") {
  const Folder dir("cli_fall");
  // 300 N for 0.2 s on a 15 kg robot: 4 m/s sideways.
  Result r = runLegkit(dir.path, {"sim", "--scenario", "physics-push", "--push", "300",
                                  "--duration", "6", "--out", "fall.csv"});
  CHECK(r.status == 3);
  CHECK_THAT(r.output, Catch::Matchers::Contains("the robot fell at t = "));
  CHECK_THAT(r.output, Catch::Matchers::Contains("wrote the log up to then"));
  const legkit::io::Log log = legkit::io::readLog((dir.path / "fall.csv").string());
  CHECK(log.rows.back().t > 3.0);  // the push starts at 3 s
  CHECK(log.rows.back().t < 6.0);
  CHECK_THAT(r.output, Catch::Matchers::Contains(std::to_string(log.rows.size()) + " rows"));
}

TEST_CASE("cli: run takes a physics scenario: every estimator, the same table", "[cli][physics]") {
  const Folder dir("cli_physics_run");
  const Result r = runLegkit(dir.path, {"run", "--scenario", "physics-trot", "--duration", "2.5",
                                        "--no-plots", "--out", "out"});
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("simulated physics-trot (MuJoCo physics), 2.5 s"));
  for (const char* name :
       {"imu-dead-reckoning", "leg-odometry", "linear-kf", "eskf", "invariant-ekf", "tsif"}) {
    CHECK_THAT(r.output, Catch::Matchers::Contains(name));
  }
  CHECK(dataRows(dir.path / "out" / "log.csv") == 2500);
  CHECK_THAT(slurp(dir.path / "out" / "summary.json"), Catch::Matchers::Contains("\"fell\": null"));
}

TEST_CASE("cli: run on a physics scenario whose robot falls: the table up to the fall, exit 3",
          "[cli][physics]") {
  const Folder dir("cli_physics_fall_run");
  // The naive controller on the ice patch (57.X) falls within its 10 s.
  const Result r =
      runLegkit(dir.path, {"run", "--scenario", "physics-ice", "--no-plots", "--out", "out"});
  INFO(r.output);
  CHECK(r.status == 3);
  CHECK_THAT(r.output, Catch::Matchers::Contains("STOPPED: the robot fell at t = "));
  CHECK_THAT(r.output, Catch::Matchers::Contains("the table covers the log up to then"));
  CHECK_THAT(r.output, Catch::Matchers::Contains("invariant-ekf"));
  const std::string summary = slurp(dir.path / "out" / "summary.json");
  CHECK_THAT(summary, Catch::Matchers::Contains("\"fell\": \"the robot fell at t = "));
  CHECK_THAT(summary, Catch::Matchers::Contains("\"exit_status\": 3"));
  const int rows = dataRows(dir.path / "out" / "log.csv");
  CHECK(rows > 3000);
  CHECK(rows < 10000);
}

TEST_CASE("cli: the main job runs on detected contacts and scores the detector", "[cli][physics]") {
  const Folder dir("cli_detected");
  Result r = runLegkit(dir.path, {"run", "--duration", "2.5", "--no-plots", "--out", "out"});
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("simulated physics-trot (MuJoCo physics), 2.5 s"));
  CHECK_THAT(r.output,
             Catch::Matchers::Contains("contacts: detected by schmitt>momentum-observer>kinematic>"
                                       "gait-clock; slip handling: inflate; rolling foot: on; "
                                       "touchdown settling: 80 ms"));
  CHECK_THAT(r.output, Catch::Matchers::Contains("against the physics' true contact"));
  CHECK_THAT(r.output, Catch::Matchers::Contains("every estimator"));
  const std::string summary = slurp(dir.path / "out" / "summary.json");
  CHECK_THAT(summary, Catch::Matchers::Contains("\"slip\": \"inflate\""));
  CHECK_THAT(summary, Catch::Matchers::Contains("\"contact_scores\""));
  CHECK_THAT(summary, Catch::Matchers::Contains("\"f1\""));
  CHECK_THAT(summary, Catch::Matchers::Contains("\"settle_time_s\": 0.08"));
  CHECK_THAT(summary, Catch::Matchers::Contains("\"training_s\": null"));

  // The old path, asked for: the log's (true) flags, no slip reaction, the sphere's centre, no
  // touchdown settling.
  r = runLegkit(dir.path, {"run", "--duration", "2.5", "--no-plots", "--out", "truth", "--contact",
                           "truth", "--slip", "none", "--no-rolling-foot", "--settle", "0"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains(
                           "contacts: the log's contact flags (--contact truth); slip handling: "
                           "none; rolling foot: off; touchdown settling: off"));
  CHECK_THAT(slurp(dir.path / "truth" / "summary.json"),
             Catch::Matchers::Contains("\"settle_time_s\": 0.0"));
  // One estimator's scores line each when the detector reads the estimate (kinematic: its roll
  // and pitch).
  r = runLegkit(dir.path, {"run", "--duration", "2.5", "--no-plots", "--out", "kin", "--contact",
                           "kinematic"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("contact detection (kinematic)"));
}

TEST_CASE("cli: the analytic trot keeps its true flags", "[cli]") {
  const Folder dir("cli_analytic");
  const Result r = runLegkit(
      dir.path, {"run", "--scenario", "trot", "--duration", "2", "--no-plots", "--out", "out"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("simulated trot, 2 s"));
  CHECK_THAT(r.output, Catch::Matchers::Contains("contacts: the log's contact flags"));
  CHECK_THAT(r.output, Catch::Matchers::Contains("touchdown settling: off"));  // ideal contacts
  CHECK_THAT(r.output, !Catch::Matchers::Contains("contact detection"));
}

TEST_CASE("cli: contact and slip options: bad values are usage errors naming them",
          "[cli][physics]") {
  const Folder dir("cli_contact_options");
  Result r = runLegkit(dir.path, {"run", "--contact", "psychic", "--out", "x"});
  CHECK(r.status == 1);
  CHECK_THAT(r.output, Catch::Matchers::Contains("--contact"));
  CHECK_THAT(r.output, Catch::Matchers::Contains("schmitt"));  // the known names are listed
  r = runLegkit(dir.path, {"run", "--slip", "sideways", "--out", "x"});
  CHECK(r.status == 1);
  CHECK_THAT(r.output, Catch::Matchers::Contains("--slip"));
  // Out of range, absurd, not a number: each refused by name (CLI11's own range check lets NaN
  // through; the settings file caps the settling at 1 s, and so does the option).
  for (const char* bad : {"-0.01", "1e308", "nan", "inf"}) {
    INFO(bad);
    r = runLegkit(dir.path, {"run", "--settle", bad, "--out", "x"});
    CHECK(r.status == 1);
    CHECK_THAT(r.output, Catch::Matchers::Contains("--settle"));
    CHECK_FALSE(fs::exists(dir.path / "x" / "summary.json"));
  }

  // A log without contact columns: 'truth' is refused, the default is a detector.
  REQUIRE(runLegkit(dir.path,
                    {"sim", "--scenario", "physics-trot", "--duration", "2.5", "--out", "p.csv"})
              .status == 0);
  legkit::io::Log log = legkit::io::readLog((dir.path / "p.csv").string());
  log.layout.contact = false;
  legkit::io::writeLog((dir.path / "no-flags.csv").string(), log);
  r = runLegkit(dir.path,
                {"run", "--log", "no-flags.csv", "--contact", "truth", "--no-plots", "--out", "x"});
  CHECK(r.status == 1);
  CHECK_THAT(r.output, Catch::Matchers::Contains("no-flags.csv has no contact columns"));
  r = runLegkit(dir.path, {"run", "--log", "no-flags.csv", "--no-plots", "--out", "x"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("contacts: detected by schmitt>"));
  CHECK_THAT(r.output, !Catch::Matchers::Contains("no contact for longer than the bound"));
}

TEST_CASE("cli: run --contact probabilistic trains the logistic model first, then runs on it",
          "[cli][physics]") {
  const Folder dir("cli_probabilistic");
  const Result r = runLegkit(dir.path, {"run", "--contact", "probabilistic", "--duration", "2.5",
                                        "--no-plots", "--out", "out"});
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains("contacts: detected by probabilistic"));
  CHECK_THAT(r.output, Catch::Matchers::Contains(
                           "logistic contact model trained on simulated physics runs (seeds "
                           "1001..1003) in "));
  CHECK_THAT(r.output, Catch::Matchers::Contains("contact detection (probabilistic)"));
  const std::string summary = slurp(dir.path / "out" / "summary.json");
  CHECK_THAT(summary, Catch::Matchers::Contains("\"source\": \"probabilistic\""));
  CHECK_THAT(summary, !Catch::Matchers::Contains("\"training_s\": null"));
}

namespace {

// The lines of a TUM trajectory file, each as its numbers.
std::vector<std::vector<double>> tumLines(const fs::path& path) {
  std::ifstream f(path);
  std::vector<std::vector<double>> lines;
  for (std::string line; std::getline(f, line);) {
    std::istringstream words(line);
    lines.emplace_back();
    for (double x = 0.0; words >> x;) lines.back().push_back(x);
  }
  return lines;
}

}  // namespace

TEST_CASE("cli: run --tum writes the estimates and the truth for evo; the table's aligned ATE",
          "[cli]") {
  const Folder dir("cli_tum");
  const fs::path out = dir.path / "out";
  fs::create_directories(out);
  Result r = runLegkit(dir.path, {"run", "--scenario", "trot", "--duration", "3", "--no-plots",
                                  "--tum", "--out", "out"});
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Catch::Matchers::Contains(" ATE se3 [m] ") &&
                           Catch::Matchers::Contains(" RPE 1m [%] ") &&
                           Catch::Matchers::Contains("ATE se3: after the least-squares SE(3)"));
  CHECK_THAT(slurp(out / "summary.json"), Catch::Matchers::Contains("\"ate_se3_rmse_m\"") &&
                                              Catch::Matchers::Contains("\"ate_4dof_rmse_m\""));
  for (const char* name : {"truth", "estimate_eskf", "estimate_imu-dead-reckoning"}) {
    INFO(name);
    const std::vector<std::vector<double>> lines = tumLines(out / (std::string(name) + ".tum"));
    // The rows of the estimate files (100 Hz): t = 0, 0.01, .. 2.99 and 2.999.
    REQUIRE(static_cast<int>(lines.size()) == dataRows(out / "estimate_eskf.csv"));
    for (std::size_t k = 0; k < lines.size(); ++k) {
      REQUIRE(lines[k].size() == 8);  // t tx ty tz qx qy qz qw
      const Eigen::Vector4d q(lines[k][4], lines[k][5], lines[k][6], lines[k][7]);
      CHECK(q.norm() == Approx(1.0).margin(1e-8));
      if (k > 0) CHECK(lines[k][0] > lines[k - 1][0]);
    }
  }
  // A run without --tum leaves no TUM file of the last one.
  r = runLegkit(dir.path,
                {"run", "--scenario", "trot", "--duration", "3", "--no-plots", "--out", "out"});
  REQUIRE(r.status == 0);
  for (const fs::directory_entry& e : fs::directory_iterator(out)) {
    CHECK(e.path().extension() != ".tum");
  }
}
