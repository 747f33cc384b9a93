#include "scenarios.hpp"

#include <algorithm>
#include <sstream>

#include "output.hpp"
#include "sim/scenario.hpp"

namespace legkit::tools {
namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

bool isPhysicsScenario(const std::string& name) {
  const std::vector<std::string> names = sim::physicsScenarioNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::vector<std::string> allScenarioNames() {
  std::vector<std::string> names = sim::scenarioNames();
  for (const std::string& n : sim::physicsScenarioNames()) names.push_back(n);
  return names;
}

std::string scenarioHelp() {
  return "analytic: " + joined(sim::scenarioNames()) +
         "; physics (MuJoCo, chapters/57.0): " + joined(sim::physicsScenarioNames());
}

FrontendNoise matchedFrontendNoise(const sim::PhysicsOptions& options) {
  FrontendNoise noise;
  noise.encoder_angle_sigma = options.encoder_angle_sigma;
  return noise;
}

void checkPushesInRun(const sim::PhysicsOptions& options) {
  for (const sim::Push& p : options.scenario.pushes) {
    if (!(p.start < options.duration)) {
      std::ostringstream os;
      os << "--duration: " << options.scenario.name << " pushes the robot at t = " << p.start
         << " s; a run of " << options.duration << " s ends before that";
      throw UsageError(os.str());
    }
  }
}

std::string describeFall(const sim::PhysicsStatus& status) {
  std::ostringstream os;
  os << (status.diverged ? "the simulation diverged at t = " : "the robot fell at t = ")
     << status.time << " s (" << status.reason << ")";
  return os.str();
}

}  // namespace legkit::tools
