// `legkit eval`'s results from its per-log rows: the table per log and estimator, the overall
// table and eval.csv, made by one function for the single-machine evaluation and for `legkit
// merge` of its shards; and the rows as a shard's manifest carries them (every number %.17g).
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace legkit::tools {

// One estimator on one log. NaN: not computed (no ground truth, a failed run, no covariance).
struct EvalEstimatorRow {
  std::string estimator;
  bool healthy = false;        // RunResult::ok()
  std::string failure;         // why it stopped or was unhealthy, empty if healthy
  double position_rmse = 0.0;  // [m]
  double ate_se3 = 0.0;        // [m], after the least-squares SE(3) alignment
  double rpe_percent = 0.0;    // translation RMSE over 1 m, % of it
  double rpe_deg = 0.0;        // rotation RMSE over 1 m [deg]
  double anees = 0.0;          // mean NEES / dof
};

// One log: its rows, or the error that kept it from being run (file and line).
struct EvalLogRow {
  std::string log;    // the file's name in the folder
  std::string error;  // empty: read and run
  int samples = 0;
  std::vector<EvalEstimatorRow> estimators;
};

nlohmann::json toJson(const std::vector<EvalLogRow>& rows);
// InputError naming `where` for rows that are not toJson's.
std::vector<EvalLogRow> evalRowsFromJson(const nlohmann::json& rows, const std::string& where);

// The exit code of an evaluation: 2 when a log could not be used, else 3 when an estimator
// failed or was unhealthy on one, else 0.
int evalStatus(const std::vector<EvalLogRow>& rows);

// The first line of the report, from the options a shard's manifest carries: the folder, the
// number of logs, the settings file.
std::string evalHeading(const nlohmann::json& options);

// Prints the table per log and the overall one (per estimator: the mean of each metric over the
// logs that computed it) on `out`, each bad log's error on `err`, writes dir/eval.csv and returns
// evalStatus(rows). `heading` is the first line.
int reportEval(std::ostream& out, std::ostream& err, const std::filesystem::path& dir,
               const std::string& heading, const std::vector<EvalLogRow>& rows);

}  // namespace legkit::tools
