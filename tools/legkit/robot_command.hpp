// `legkit robot`: the robot of a settings file as the kit understands it, the tape-measure check
// of section 57.11 before any filter runs.
//   legkit robot my.yaml                      model, base, mass, joints in log-column order, feet
//                                             in the base frame at zero angles
//   legkit robot my.yaml --angles 0,0.8,-1.6  the feet at those angles too (joint order above)
//   legkit robot my.yaml --log run.csv        refuses a log whose joint columns are not the
//                                             robot's in kind (generic or the quadruped's) or in
//                                             number (names are not in a log); the feet at its
//                                             first row
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace legkit::tools {

class RobotCommand {
 public:
  // Registers the `robot` subcommand and its options on `app`.
  explicit RobotCommand(CLI::App& app);
  RobotCommand(const RobotCommand&) = delete;  // the options are bound to this object's members
  RobotCommand& operator=(const RobotCommand&) = delete;

  bool parsed() const { return static_cast<bool>(*command_); }
  // Returns the exit code. A settings file, model or log the kit cannot use throws (exit 2); angles
  // of the wrong count throw UsageError (exit 1).
  int run(std::ostream& out) const;

 private:
  CLI::App* command_;
  std::string settings_;
  std::vector<double> angles_;
  std::string log_;
};

}  // namespace legkit::tools
