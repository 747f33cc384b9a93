// `legkit eval DIR --config FILE`: every log (*.csv) of a folder, in name order, through the
// settings' estimators as `legkit run --log F --config FILE` runs one (eval::runWithSettings),
// one table row per log and estimator (position RMSE, ATE, RPE, ANEES, health) and the overall
// table. A log that cannot be used gets its error (file and line) in its row, the others finish,
// and the exit code says so (eval_report.hpp). `--shard i/N` evaluates a block of the logs into
// --out (default legkit-out/eval-<folder>-shard-<i>-of-<N>) for `legkit merge` (shard.hpp).
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

namespace legkit::tools {

class EvalCommand {
 public:
  explicit EvalCommand(CLI::App& app);
  EvalCommand(const EvalCommand&) = delete;  // the options are bound to this object's members
  EvalCommand& operator=(const EvalCommand&) = delete;

  bool parsed() const { return static_cast<bool>(*command_); }
  // The exit code; a folder or settings file the kit cannot use throws (exit 2).
  int run(std::ostream& out) const;

 private:
  CLI::App* command_;
  std::string dir_;
  std::string config_;
  std::string shard_ = "1/1";
  std::string out_;
};

}  // namespace legkit::tools
