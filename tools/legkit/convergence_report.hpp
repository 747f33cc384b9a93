// `legkit study convergence`'s results from its per-run rows (the time each run of each filter
// converged at each initial angle, or not): the table and convergence.csv, made by one function
// for the single-machine study and for `legkit merge` of its shards (shard.hpp), and the rows a
// shard writes (rows.csv) and the merge reads.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "shard.hpp"

namespace legkit::tools {

// Runs first..first + count - 1 at every angle and of every filter: time[a][e][j - first] is the
// time from the start at which run j converged, NaN when it did not.
struct ConvergenceRows {
  int first = 0;
  int count = 0;
  std::vector<double> angles;  // [deg]
  std::vector<std::string> filters;
  std::vector<std::vector<std::vector<double>>> time;  // [s]
};
// angles x filters x count slots, NaN (not converged) until set.
ConvergenceRows convergenceRows(int first, int count, std::vector<double> angles,
                                std::vector<std::string> filters);

// "angles,<deg>...", "filters,<name>...", then per angle, run and filter
// "run,<j>,<angle_deg>,<filter>,<time or nan>" with every bit (%.17g).
void writeConvergenceRows(std::ostream& out, const ConvergenceRows& rows);
// Reads what writeConvergenceRows wrote, expecting runs block.begin..block.end - 1; InputError
// naming the file and line otherwise.
ConvergenceRows readConvergenceRows(const std::filesystem::path& path, const Block& block);
// Appends the next shard's runs; InputError when its angles or filters differ.
void appendConvergenceRows(ConvergenceRows& all, const ConvergenceRows& next,
                           const std::string& where);

// The study's table on `out` and dir/convergence.csv from all `runs` runs (first == 0).
void reportConvergence(std::ostream& out, const std::filesystem::path& dir,
                       const ConvergenceRows& rows, double duration);

}  // namespace legkit::tools
