// legkit-study: the Monte Carlo studies (`legkit study ...`, study_command.hpp) as a program of
// their own, so that the main job's `legkit` does not wait on the studies' code (the Ceres
// smoother of 57.8 among it) to build. `legkit study ARGS` runs `legkit-study study ARGS`.
#include <CLI/CLI.hpp>
#include <iostream>
#include <stdexcept>

#include "output.hpp"
#include "study_command.hpp"

int main(int argc, char** argv) {
  using namespace legkit::tools;
  CLI::App app{"legkit study: the Monte Carlo studies behind the chapters' figures", "legkit"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "legkit " LEGKIT_VERSION);
  StudyCommand study(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }
  try {
    return study.run(std::cout);
  } catch (const UsageError& e) {
    std::cerr << "legkit: " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << "legkit: " << e.what() << "\n";
    return kExitInput;
  } catch (...) {
    std::cerr << "legkit: an unexpected error that is not a std::exception\n";
    return kExitInput;
  }
}
