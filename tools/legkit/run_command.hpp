// `legkit run`, the main job: simulate the default scenario (or read a recorded log), run every
// estimator of the kit on it, print one table, and write the log, the estimates and plots to an
// output folder.
//   legkit run                          trot, 60 s, Go2-class sensors, seed 1
//   legkit run --scenario turn --seed 3
//   legkit run --scenario physics-trot --duration 20   (MuJoCo physics; a fall exits 3)
//   legkit run --log my_robot.csv --json
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "eval/metrics.hpp"
#include "eval/runner.hpp"

namespace legkit::tools {

// One estimator's line of the table: its run and, when the log has ground truth and the run
// finished, its accuracy.
struct RunRow {
  eval::RunResult run;
  std::optional<eval::Metrics> metrics;
};

// The rows of a trajectory that an estimate file at `rate` [Hz] keeps (rate 0: every row): the
// first row, then the first row of each new period 1/rate counted from the first row's time, and
// the last row. Only the files are thinned; the metrics use every row.
std::vector<std::size_t> estimateRows(const std::vector<EstimateSample>& trajectory, double rate);

// The table of `legkit run`: one line per estimator (FAILED for a run that stopped), then under it
// each failure with its file:line, time and reason, and each estimator's non-zero health counts.
void printRunTable(std::ostream& out, const std::vector<RunRow>& rows);

class RunCommand {
 public:
  explicit RunCommand(CLI::App& app);
  RunCommand(const RunCommand&) = delete;  // the options are bound to this object's members
  RunCommand& operator=(const RunCommand&) = delete;

  bool parsed() const { return static_cast<bool>(*command_); }
  // Returns the exit code (tools/legkit/output.hpp); command_line goes into summary.json.
  int run(std::ostream& out, const std::string& command_line) const;

 private:
  CLI::App* command_;
  CLI::Option* duration_option_;
  std::string scenario_ = "trot";
  double duration_ = 60.0;
  unsigned seed_ = 1;
  std::string log_;
  double max_gap_ = 0.0;  // 0: 10 median periods
  std::string out_dir_;
  double estimate_rate_ = 100.0;  // [Hz] of the estimate files; 0: every sample
  bool json_ = false;
  bool plots_ = true;
};

}  // namespace legkit::tools
