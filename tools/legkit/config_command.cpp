#include "config_command.hpp"

#include "estimation/settings.hpp"
#include "model/mujoco_kinematics.hpp"
#include "output.hpp"
#include "validators.hpp"

namespace legkit::tools {

ConfigCommand::ConfigCommand(CLI::App& app)
    : command_(
          app.add_subcommand("config", "The settings file: print the defaults, check a file")) {
  CLI::App& c = *command_;
  CLI::Option* print =
      c.add_flag("--print", print_, "Write the default settings, every key documented, to stdout");
  // Not CLI::ExistingFile: a file that cannot be read is an input error (exit 2) like a bad one.
  CLI::Option* check =
      c.add_option("--check", check_,
                   "Read this settings file and load its robot model: print 'ok', or "
                   "the error naming its line and key (exit 2)")
          ->check(nonEmptyName());
  print->excludes(check);
  c.require_option(1);
}

int ConfigCommand::run(std::ostream& out) const {
  if (print_) {
    out << settingsYaml(defaultSettings());
    return kExitOk;
  }
  // Throws io::ConfigError, or the model's error for a robot section the run would refuse: main
  // prints it and exits 2.
  const Settings settings = loadSettings(check_);
  const RobotSettings& robot = settings.robot;
  try {
    model::makeLegKinematics(robot.model, robot.base, robot.feet, robot.joints);
  } catch (const std::runtime_error& e) {
    throw InputError(check_ + ": robot.model: " + e.what());  // as legkit run says it
  }
  out << "ok\n";
  return kExitOk;
}

}  // namespace legkit::tools
