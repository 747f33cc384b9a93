// Every estimator of the kit by name, with its default parameters: what `legkit run`, the Monte
// Carlo studies and the benchmarks put side by side.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "estimation/estimator.hpp"

namespace legkit {

struct Settings;  // estimation/settings.hpp

// In the order of the chapter (and of `legkit run`'s table): the names makeEstimator() knows.
// Written out here, not collected from the factories, so that the settings reader can offer them
// without linking every filter.
inline std::vector<std::string> estimatorNames() {
  return {"imu-dead-reckoning", "leg-odometry", "linear-kf", "eskf", "invariant-ekf", "tsif"};
}

// A new estimator with its default parameters. Throws std::invalid_argument for an unknown name
// (the message lists the known ones).
std::unique_ptr<Estimator> makeEstimator(const std::string& name);

// An estimator of estimatorNames() with its parameters from the settings: the IMU densities, the
// limits, the priors, the feet and its own section. Throws std::invalid_argument for an unknown
// name (listing the known ones).
std::unique_ptr<Estimator> makeEstimator(const std::string& name, const Settings& settings);

}  // namespace legkit
