// Your solution to exercise 57.8.2 (the code part; the discussion goes in answer.md). Replace the
// throws with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_8_2.hpp"

namespace ex57_8_2 {

LegDelta preintegrate(const std::vector<LegSample>& /*samples*/, const Eigen::Vector3d& /*b_v*/) {
  throw legkit::NotImplemented("preintegrate");
}

Eigen::Vector3d correctedDelta(const LegDelta& /*d*/, const Eigen::Vector3d& /*b_v*/) {
  throw legkit::NotImplemented("correctedDelta");
}

Eigen::Vector3d velocityBiasFromPoses(const LegDelta& /*d*/, const lie::SO3d& /*R_i*/,
                                      const Eigen::Vector3d& /*p_i*/,
                                      const Eigen::Vector3d& /*p_j*/) {
  throw legkit::NotImplemented("velocityBiasFromPoses");
}

}  // namespace ex57_8_2
