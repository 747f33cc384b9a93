// The legkit command line. `legkit --help` lists the subcommands.
#include <CLI/CLI.hpp>
#include <iostream>

#include "cassie_command.hpp"
#include "lie_accuracy.hpp"
#include "run_command.hpp"
#include "sim_command.hpp"
#include "study_command.hpp"
#include "tour.hpp"

int main(int argc, char** argv) {
  CLI::App app{"legkit: legged-robot state estimation, a teaching and reference kit"};
  app.require_subcommand(1);

  legkit::tools::RunCommand run(app);

  unsigned seed = 1;
  CLI::App* tour = app.add_subcommand("tour", "Identities of lie/ checked on random elements");
  tour->add_option("--seed", seed, "Random seed")->capture_default_str();

  std::string accuracyCsv;
  int accuracyPoints = 400;
  CLI::App* accuracy = app.add_subcommand(
      "lie-accuracy", "Accuracy of lie/'s angle coefficients vs naive closed forms (figure data)");
  accuracy->add_option("--csv", accuracyCsv, "Write one row per theta to this CSV file");
  accuracy->add_option("--points", accuracyPoints, "Grid points from 1e-10 to pi")
      ->capture_default_str();

  legkit::tools::SimCommand sim(app);
  legkit::tools::StudyCommand study(app);
  legkit::tools::CassieCommand cassie(app);

  CLI11_PARSE(app, argc, argv);
  try {
    if (run.parsed()) return run.run(std::cout);
    if (*tour) return legkit::tools::lieTour(std::cout, seed);
    if (*accuracy) return legkit::tools::lieAccuracy(std::cout, accuracyCsv, accuracyPoints);
    if (sim.parsed()) return sim.run(std::cout);
    if (study.parsed()) return study.run(std::cout);
    if (cassie.parsed()) return cassie.run(std::cout);
  } catch (const std::exception& e) {
    std::cerr << "legkit: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
