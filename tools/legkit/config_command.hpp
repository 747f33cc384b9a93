// `legkit config`: the settings file (estimation/settings.hpp).
//   legkit config --print             the defaults, every key with its meaning and unit
//   legkit config --check my.yaml     "ok", or the first error as file:line: key: what (exit 2);
//                                     the robot model is loaded too, as a run would
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

namespace legkit::tools {

class ConfigCommand {
 public:
  // Registers the `config` subcommand and its options on `app`.
  explicit ConfigCommand(CLI::App& app);
  ConfigCommand(const ConfigCommand&) = delete;  // the options are bound to this object's members
  ConfigCommand& operator=(const ConfigCommand&) = delete;

  bool parsed() const { return static_cast<bool>(*command_); }
  // Returns the exit code; a file that fails the check throws (io::ConfigError: exit 2).
  int run(std::ostream& out) const;

 private:
  CLI::App* command_;
  bool print_ = false;
  std::string check_;
};

}  // namespace legkit::tools
