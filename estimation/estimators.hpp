// Every estimator of the kit by name, with its default parameters: what `legkit run`, the Monte
// Carlo studies and the benchmarks put side by side.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "estimation/estimator.hpp"

namespace legkit {

// In the order of the chapter (and of `legkit run`'s table).
std::vector<std::string> estimatorNames();

// A new estimator with its default parameters. Throws std::invalid_argument for an unknown name
// (the message lists the known ones).
std::unique_ptr<Estimator> makeEstimator(const std::string& name);

}  // namespace legkit
