// An estimated trajectory: one EstimateSample (estimation/estimate.hpp) per log row.
#pragma once

#include <vector>

#include "estimation/estimate.hpp"

namespace legkit::eval {

using Trajectory = std::vector<EstimateSample>;

}  // namespace legkit::eval
