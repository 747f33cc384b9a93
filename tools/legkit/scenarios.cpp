#include "scenarios.hpp"

#include <algorithm>
#include <sstream>

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

std::string describeFall(const sim::PhysicsStatus& status) {
  std::ostringstream os;
  os << "the robot fell at t = " << status.time << " s (" << status.reason << ")";
  return os.str();
}

}  // namespace legkit::tools
