// The legkit command line. `legkit --help` lists the subcommands.
#include <CLI/CLI.hpp>
#include <iostream>

#include "tour.hpp"

int main(int argc, char** argv) {
  CLI::App app{"legkit: legged-robot state estimation, a teaching and reference kit"};
  app.require_subcommand(1);

  unsigned seed = 1;
  CLI::App* run = app.add_subcommand(
      "run", "The main job. Until the estimators land it runs the Lie-group tour");
  run->add_option("--seed", seed, "Random seed")->capture_default_str();

  CLI::App* tour = app.add_subcommand("tour", "Identities of lie/ checked on random elements");
  tour->add_option("--seed", seed, "Random seed")->capture_default_str();

  CLI11_PARSE(app, argc, argv);
  try {
    if (*run || *tour) return legkit::tools::lieTour(std::cout, seed);
  } catch (const std::exception& e) {
    std::cerr << "legkit: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
