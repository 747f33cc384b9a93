// The scenario names `legkit sim` and `legkit run` take: the analytic simulator's
// (sim/scenario.hpp) and the physics simulator's (sim/physics_simulator.hpp, MuJoCo).
#pragma once

#include <string>
#include <vector>

#include "estimation/log_frontend.hpp"
#include "sim/physics_simulator.hpp"

namespace legkit::tools {

bool isPhysicsScenario(const std::string& name);
// The analytic names, then the physics ones.
std::vector<std::string> allScenarioNames();
// For --help: "analytic: stand, walk, ...; physics (MuJoCo): physics-stand, ...".
std::string scenarioHelp();
// The front end's noise matched to the physics simulator's encoders, as eval::matchedFrontendNoise
// does for the analytic one (so that ANEES measures the filters, not a mismatched model).
FrontendNoise matchedFrontendNoise(const sim::PhysicsOptions& options);
// A UsageError naming --duration when the run ends before one of the scenario's pushes starts.
void checkPushesInRun(const sim::PhysicsOptions& options);
// "the robot fell at t = 3.412 s (reason)", or for MuJoCo's reset on bad numbers "the simulation
// diverged at t = ... s (reason)".
std::string describeFall(const sim::PhysicsStatus& status);

}  // namespace legkit::tools
