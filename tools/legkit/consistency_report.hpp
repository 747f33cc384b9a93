// `legkit study consistency`'s and `legkit study sweep`'s results from their per-run rows: what
// each study prints and writes (consistency.csv, sweep.csv), made by one function for the
// single-machine study and for `legkit merge` of its shards (shard.hpp), and the per-run rows a
// shard writes (rows.csv) and the merge reads.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "eval/monte_carlo.hpp"
#include "shard.hpp"

namespace legkit::tools {

// Runs first..first + runs[e].size() - 1 of every estimator or setting e, each run as
// eval::reduceRuns takes it (of the metrics, only the position and velocity RMSE are kept), and
// a study's own numbers per run (extra[e][j - first]: the sweep's velocity bias and variance).
struct MonteCarloRows {
  int first = 0;
  std::vector<std::string> names;                       // filters, or the sweep's settings
  std::vector<double> t;                                // the time of each row [s]
  std::vector<std::vector<eval::RunSummary>> runs;      // runs[e][j - first]
  std::vector<std::vector<std::vector<double>>> extra;  // extra[e][j - first]
};

// The rows with every bit (%.17g): "t,<values>", "names,<names>", then per run and name e
// "run,<j>,<e's name>,<dof>,<position_rmse>,<velocity_rmse>,<us_per_step>,<number of extras>,
// <extras>,<nees values>".
void writeMonteCarloRows(std::ostream& out, const MonteCarloRows& rows);
// Reads what writeMonteCarloRows wrote, expecting runs block.begin..block.end - 1; InputError
// naming the file and line otherwise.
MonteCarloRows readMonteCarloRows(const std::filesystem::path& path, const Block& block);
// Appends the next shard's rows (its runs follow all's); InputError when its names or times
// differ.
void appendMonteCarloRows(MonteCarloRows& all, const MonteCarloRows& next,
                          const std::string& where);

// The study's table on `out` and dir/consistency.csv, from all runs (first == 0): the ANEES of
// each filter through eval::reduceRuns, and each run's yaw RMSE from its extra value. The header
// says whether the filters were the plain ones (`correct_yaw`) or the heading rule's.
void reportConsistency(std::ostream& out, const std::filesystem::path& dir,
                       const MonteCarloRows& rows, double duration, bool correct_yaw);

// The sweep's settings, in its order: "<parameter> x <scale>" (sweepSetting), 3 x 13 of them.
inline constexpr const char* kSweepParameters[] = {"foot process noise", "accelerometer noise",
                                                   "measurement noise"};
inline constexpr int kSweepScales = 13;      // 10^(0.5 i), i = -6..6
inline constexpr double kSweepWindow = 1.0;  // [s] of the bias-variance split: two strides
double sweepScale(int i);                    // i = 0..12
std::string sweepSetting(int parameter, int i);

// The sweep's table on `out` and dir/sweep.csv from all runs (first == 0): per setting the mean
// position and velocity RMSE, the velocity bias (root of the mean of the runs' squared biases)
// and variance (extra[e][j] = {bias, variance}), and the ANEES through eval::reduceRuns.
void reportSweep(std::ostream& out, const std::filesystem::path& dir, const MonteCarloRows& rows,
                 double duration);

}  // namespace legkit::tools
