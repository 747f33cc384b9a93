// legkit.sim: the scenarios of chapter 57.0 (sim/scenario.hpp: analytic; sim/physics_scenario.hpp:
// MuJoCo physics) to a log in memory, as `legkit sim` writes them to a file.
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "estimation/settings.hpp"
#include "eval/monte_carlo.hpp"
#include "sim/physics_simulator.hpp"
#include "sim/simulator.hpp"
#include "tools/legkit/scenarios.hpp"

namespace py = pybind11;

namespace legkit::python {

void bindSim(py::module_& m) {
  m.def("scenario_names", &tools::allScenarioNames,
        "The analytic scenarios (stand, walk, trot, ...), then the physics ones (physics-...)");
  m.def(
      "simulate",
      [](const std::string& scenario, std::optional<double> duration, unsigned seed, double rate,
         bool noiseless, bool ground_truth) {
        if (tools::isPhysicsScenario(scenario)) {
          sim::PhysicsOptions options = sim::PhysicsOptions::forScenario(scenario);
          if (duration) options.duration = *duration;
          options.seed = seed;
          options.rate = rate;
          if (noiseless) options.noiseless();
          options.ground_truth = ground_truth;
          tools::checkPushesInRun(options);
          sim::PhysicsResult result;
          {
            py::gil_scoped_release release;
            result = sim::simulatePhysics(options);
          }
          if (result.status.fell) {
            throw std::runtime_error(scenario + ": " + tools::describeFall(result.status));
          }
          return std::move(result.log);
        }
        sim::SimOptions options;
        options.scenario = sim::scenarioByName(scenario);
        if (duration) options.duration = *duration;
        options.seed = seed;
        options.rate = rate;
        if (noiseless) options.noiseless();
        options.ground_truth = ground_truth;
        py::gil_scoped_release release;
        return sim::simulate(options).log;
      },
      py::arg("scenario") = "trot", py::arg("duration") = py::none(), py::arg("seed") = 1,
      py::arg("rate") = 1000.0, py::arg("noiseless") = false, py::arg("ground_truth") = true,
      "Simulates a scenario to a legkit.io.Log, as `legkit sim` does: Go2-class sensors at `rate` "
      "[Hz], `duration` [s] (None: 60 s analytic, the physics scenario's own length), noise and "
      "biases from `seed` (noiseless: exact readings). Physics scenarios (MuJoCo) also log the "
      "true contact of each foot (gt_contact_*). Raises ValueError for a bad option and "
      "RuntimeError when the physics robot falls. The GIL is released while it runs.");
  m.def(
      "settings_for",
      [](const std::string& scenario, unsigned seed) {
        // As `legkit run --scenario` runs it: the front end told the simulator's own sensor
        // noise (so that NEES measures the filters, not a mismatched model); the analytic
        // scenarios keep their true contact flags, with no slip check, rolling foot or settling,
        // and the estimators' own leg noise (exact legs).
        Settings s = defaultSettings();
        if (tools::isPhysicsScenario(scenario)) {
          sim::PhysicsOptions options = sim::PhysicsOptions::forScenario(scenario);
          options.seed = seed;
          s.frontend = tools::matchedFrontendNoise(options);
          return s;
        }
        sim::SimOptions options;
        options.scenario = sim::scenarioByName(scenario);
        options.seed = seed;
        s.frontend = eval::matchedFrontendNoise(options);
        s.pipeline.contact = "truth";
        s.pipeline.slip = slip::SlipReaction::kNone;
        s.pipeline.rolling_foot = false;
        s.pipeline.settle_time = 0.0;
        return withExactLegs(s);  // the estimators' own leg noise
      },
      py::arg("scenario") = "trot", py::arg("seed") = 1,
      "The settings `legkit run --scenario NAME` runs a simulated log with: the kit's defaults, "
      "the front end told the simulator's sensor noise, and on the analytic scenarios the true "
      "contact flags (no detector, slip check, rolling foot or settling) and the estimators' own "
      "leg noise (exact legs)");
}

}  // namespace legkit::python
