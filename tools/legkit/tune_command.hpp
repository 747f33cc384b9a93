// `legkit tune`: the noise settings that matter fitted to a recorded log, cross-validated
// (eval/tuning.hpp says what is fitted, on which score, and why not with Ceres), e.g.
//   legkit tune run.csv --config my_robot.yaml             fits on the first half, reports on the
//                                                          second, writes the tuned settings
//   legkit tune run.csv --config my_robot.yaml --out t.yaml --estimator invariant-ekf
// It prints each parameter before and after (or why it kept it), every estimator on the part the
// fit never saw with the settings given and the tuned ones, and the changed keys as YAML; the
// whole tuned settings file goes to --out (default legkit-out/<log>-tuned.yaml).
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

namespace legkit::tools {

class TuneCommand {
 public:
  // Registers the `tune` subcommand and its options on `app`.
  explicit TuneCommand(CLI::App& app);
  TuneCommand(const TuneCommand&) = delete;  // the options are bound to this object's members
  TuneCommand& operator=(const TuneCommand&) = delete;

  bool parsed() const { return static_cast<bool>(*command_); }
  // Returns the exit code. A log, settings file or robot the kit cannot use throws (exit 2).
  int run(std::ostream& out) const;

 private:
  CLI::App* command_;
  std::string log_;
  std::string config_;
  std::string estimator_ = "eskf";
  double fit_share_ = 0.5;
  std::string out_;
};

}  // namespace legkit::tools
