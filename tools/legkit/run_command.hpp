// `legkit run`, the main job: simulate the default scenario (or read a recorded log), run every
// estimator of the kit on it, print one table, and write the log, the estimates and plots to an
// output folder.
//   legkit run                          trot, 60 s, Go2-class sensors, seed 1
//   legkit run --scenario turn --seed 3
//   legkit run --log my_robot.csv --json
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

namespace legkit::tools {

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
  std::string scenario_ = "trot";
  double duration_ = 60.0;
  unsigned seed_ = 1;
  std::string log_;
  double max_gap_ = 0.0;  // 0: 10 median periods
  std::string out_dir_;
  bool json_ = false;
  bool plots_ = true;
};

}  // namespace legkit::tools
