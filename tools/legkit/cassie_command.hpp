// `legkit cassie [FILE]`: runs the right-invariant EKF on the reference implementation's Cassie
// log (RossHartley/invariant-ekf, src/data/imu_kinematic_measurements.txt; io/hartley_log.hpp)
// with the reference's settings, and prints the final state, e.g.
//   legkit cassie                      the log of data/hartley-cassie/ (unpacked by CMake)
//   legkit cassie --reference          the reference's touchdown attitude: its own output
//   legkit cassie my_log.txt --exact   another log in that format; the kit's exact Phi
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

#include "estimation/invariant/invariant_ekf.hpp"
#include "io/hartley_log.hpp"

namespace legkit::tools {

class CassieCommand {
 public:
  // Registers the `cassie` subcommand and its options on `app`.
  explicit CassieCommand(CLI::App& app);
  CassieCommand(const CassieCommand&) = delete;  // the options are bound to this object's members
  CassieCommand& operator=(const CassieCommand&) = delete;

  bool parsed() const { return static_cast<bool>(*command_); }
  // Reads the log, runs the filter, prints the final state. Returns the exit code.
  int run(std::ostream& out) const;

 private:
  CLI::App* command_;
  std::string file_;
  bool exact_ = false;
  bool reference_ = false;  // TouchdownAttitude::kPredicted
};

}  // namespace legkit::tools
