// The legkit command line. `legkit --help` lists the subcommands.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>

#include "io/log_error.hpp"
#include "output.hpp"

#include "allan_command.hpp"
#include "cassie_command.hpp"
#include "config_command.hpp"
#include "eval_command.hpp"
#include "lie_accuracy.hpp"
#include "merge_command.hpp"
#include "robot_command.hpp"
#include "run_command.hpp"
#include "sim_command.hpp"
#include "tour.hpp"
#include "tune_command.hpp"
#include "validators.hpp"

namespace {

// `legkit study ARGS` is the program legkit-study beside this one (study_main.cpp), given
// `study ARGS`: it returns only when that program cannot be started.
int runStudyProgram(char** argv) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  const fs::path program = (error ? fs::path(argv[0]) : self).parent_path() / "legkit-study";
  argv[0] = const_cast<char*>(program.c_str());
  execv(program.c_str(), argv);
  std::cerr << "legkit: cannot run " << program.string() << " (" << std::strerror(errno)
            << "): `legkit study` is that program; build it with `cmake --build build --target "
               "legkit-study`\n";
  return legkit::tools::kExitInput;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace legkit::tools;
  if (argc > 1 && std::string(argv[1]) == "study") return runStudyProgram(argv);
  CLI::App app{"legkit: legged-robot state estimation, a teaching and reference kit"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "legkit " LEGKIT_VERSION);
  app.footer(
      "Exit codes: 0 done, every estimator healthy; 1 the command line was wrong; 2 the input\n"
      "could not be used or an output not written (nothing reported as done); 3 the run\n"
      "finished but an estimator failed, had to recover or could not use more than 5 % of its\n"
      "input (the table says which and where),\n"
      "or the simulated robot fell or its simulation diverged (when and why are printed; the\n"
      "log ends there).");

  legkit::tools::RunCommand run(app);

  unsigned seed = 1;
  CLI::App* tour = app.add_subcommand("tour", "Identities of lie/ checked on random elements");
  tour->add_option("--seed", seed, "Random seed")->check(seedNumber())->capture_default_str();

  std::string accuracyCsv;
  int accuracyPoints = 400;
  CLI::App* accuracy = app.add_subcommand(
      "lie-accuracy", "Accuracy of lie/'s angle coefficients vs naive closed forms (figure data)");
  accuracy->add_option("--csv", accuracyCsv, "Write one row per theta to this CSV file")
      ->check(nonEmptyName());
  // At least the two ends of the grid; a million points take about a second and 100 MB.
  accuracy->add_option("--points", accuracyPoints, "Grid points from 1e-10 to pi")
      ->check(wholeRange(2, 1000000))
      ->capture_default_str();

  legkit::tools::SimCommand sim(app);
  // Listed for --help; `legkit study ...` never reaches the parser (runStudyProgram).
  app.add_subcommand("study",
                     "Monte Carlo studies behind the chapters' figures (legkit study --help)");
  legkit::tools::CassieCommand cassie(app);
  legkit::tools::AllanCommand allan(app);
  legkit::tools::ConfigCommand config(app);
  legkit::tools::RobotCommand robot(app);
  legkit::tools::TuneCommand tune(app);
  legkit::tools::EvalCommand eval(app);    // a folder of logs, shardable (--shard i/N)
  legkit::tools::MergeCommand merge(app);  // the shards of a study or eval combined

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;  // --help and --version exit 0
  }
  std::string command_line;
  for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);
  int status = kExitOk;
  try {
    status = [&] {
      if (run.parsed()) return run.run(std::cout, command_line);
      if (*tour) return legkit::tools::lieTour(std::cout, seed);
      if (*accuracy) return legkit::tools::lieAccuracy(std::cout, accuracyCsv, accuracyPoints);
      if (sim.parsed()) return sim.run(std::cout);
      if (cassie.parsed()) return cassie.run(std::cout);
      if (allan.parsed()) return allan.run(std::cout);
      if (config.parsed()) return config.run(std::cout);
      if (robot.parsed()) return robot.run(std::cout);
      if (tune.parsed()) return tune.run(std::cout);
      if (eval.parsed()) return eval.run(std::cout);
      if (merge.parsed()) return merge.run(std::cout);
      return static_cast<int>(kExitOk);
    }();
  } catch (const UsageError& e) {  // e.g. an unknown leg or a malformed --dropout
    std::cerr << "legkit: " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::exception& e) {  // the input or an output: LogError, InputError, ...
    std::cerr << "legkit: " << e.what() << "\n";
    return kExitInput;
  } catch (...) {
    std::cerr << "legkit: an unexpected error that is not a std::exception\n";
    return kExitInput;
  }
  // A report that did not reach its reader is not done (stdout on a full disk: `legkit config
  // --print > /dev/full` printed nothing and exited 0).
  std::cout.flush();
  if (!std::cout) {
    std::cerr << "legkit: cannot write the standard output\n";
    return kExitInput;
  }
  return status;
}
