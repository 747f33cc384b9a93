// `legkit sim`: simulate a scenario and write its log (io/ format), e.g.
//   legkit sim --scenario trot --duration 60 --seed 1 --out log.csv
//   legkit sim --scenario trot --slip-foot FR --slip-start 5 --slip-duration 0.5 --slip-speed 0.3
//   legkit sim --scenario physics-trot --duration 20 --out trot.csv      (MuJoCo physics)
//   legkit sim --scenario physics-push --push 80
//   legkit sim --scenario physics-trot --closed-loop "Invariant EKF"
// A physics run whose robot falls exits 3, saying when and why, and writes the log up to the fall.
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace legkit::tools {

class SimCommand {
 public:
  // Registers the `sim` subcommand and its options on `app`.
  explicit SimCommand(CLI::App& app);
  SimCommand(const SimCommand&) = delete;  // the options are bound to this object's members
  SimCommand& operator=(const SimCommand&) = delete;

  bool parsed() const { return static_cast<bool>(*command_); }
  // Simulates and writes the log; prints a one-line summary. Returns the exit code.
  int run(std::ostream& out) const;

 private:
  int runAnalytic(std::ostream& out) const;
  int runPhysics(std::ostream& out) const;

  CLI::App* command_;
  CLI::Option* duration_option_;
  std::vector<CLI::Option*> analytic_only_;  // the fault and foot-column options
  std::vector<CLI::Option*> slip_options_;   // --slip-start, ... (only with --slip-foot)
  CLI::Option* friction_option_;
  CLI::Option* push_option_;
  CLI::Option* closed_loop_option_;
  std::string scenario_ = "trot";
  double duration_ = 60.0;
  double rate_ = 1000.0;
  unsigned seed_ = 1;
  std::string out_ = "log.csv";
  bool noiseless_ = false;
  bool no_ground_truth_ = false;
  std::string foot_columns_ = "none";
  std::string slip_foot_;
  double slip_start_ = 5.0;
  double slip_duration_ = 0.5;
  double slip_speed_ = 0.3;
  std::vector<double> slip_direction_{1.0, 0.0};
  double contact_offset_ = 0.0;
  std::vector<std::string> dropouts_;
  double dropout_probability_ = 0.0;
  double friction_ = 0.6;  // physics: ground friction coefficient
  double push_ = 0.0;      // physics: lateral push force [N]
  std::string closed_loop_;
};

}  // namespace legkit::tools
