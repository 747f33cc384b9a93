// The simulated trot the filter tests run on, and its rows as estimator inputs.
#pragma once

#include <vector>

#include "estimation/log_frontend.hpp"
#include "sim/simulator.hpp"

namespace legkit::test {

// `duration` seconds of the default trot from `seed`; exact readings when `noiseless`.
inline io::Log trotLog(double duration, unsigned seed, bool noiseless,
                       const model::ImuBias& bias = model::ImuBias{}) {
  sim::SimOptions options;
  options.scenario = sim::scenarioByName("trot");
  options.duration = duration;
  options.seed = seed;
  options.initial_bias = bias;
  if (noiseless) options.noiseless();
  return sim::simulate(options).log;
}

inline std::vector<StepInput> inputsOf(const io::Log& log, const FrontendNoise& noise = {}) {
  return LogFrontend(log.layout, model::QuadrupedKinematics(), noise).inputs(log);
}

}  // namespace legkit::test
