// `legkit allan`: the Allan deviation of a resting IMU and the kit's noise parameters read from it
// (section 57.10, estimation/imu/allan.hpp, chapters/57.10-allan-variance.md), e.g.
//   legkit allan imu.csv                   a recording: the kit's log, or plain t,gx,gy,gz,ax,ay,az
//   legkit allan --simulate 7200           two hours of the kit's Go2 IMU model at rest, 1 kHz
// It prints per axis the white-noise density, the bias random walk and the bias instability, then
// the settings file's imu: section, and writes to the output folder allan.csv (tau, adev and its
// bounds per axis), allan-lines.csv (the fitted lines), imu-noise.yaml and allan.png.
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

#include "estimation/imu/allan.hpp"

namespace legkit::tools {

// The settings file's imu: section with the four measured keys; a key whose line the record does
// not show is left out, with a comment saying why.
std::string imuNoiseYaml(const imu::AllanAnalysis& analysis, const std::string& source);

class AllanCommand {
 public:
  // Registers the `allan` subcommand and its options on `app`.
  explicit AllanCommand(CLI::App& app);
  AllanCommand(const AllanCommand&) = delete;  // the options are bound to this object's members
  AllanCommand& operator=(const AllanCommand&) = delete;

  bool parsed() const { return static_cast<bool>(*command_); }
  // Reads (or simulates) the recording, analyses it, prints and writes the results. Returns the
  // exit code; an input that cannot be used throws (io::LogError, InputError: exit 2).
  int run(std::ostream& out) const;

 private:
  CLI::App* command_;
  std::string file_;
  double simulate_ = 0.0;  // seconds of a simulated resting Go2 IMU (0: read file_)
  double rate_ = 1000.0;   // its sample rate [Hz]
  unsigned seed_ = 1;
  std::string out_dir_;
  imu::AllanOptions options_;
  bool plots_ = true;
};

}  // namespace legkit::tools
