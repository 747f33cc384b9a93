// Your solution to exercise 57.2.1. Replace each throw with your implementation (Eigen only:
// write Exp with the Rodrigues formula and the rotation-vector extraction yourself).
#include <legkit/not_implemented.hpp>

#include "ex57_2_1.hpp"

namespace ex57_2_1 {

Eigen::Matrix3d rodriguesStep(const Eigen::Matrix3d& /*R*/, const Eigen::Vector3d& /*w*/,
                              double /*dt*/) {
  throw legkit::NotImplemented("rodriguesStep");
}

Eigen::Vector3d attitudeErrorFromBias(const Eigen::Vector3d& /*b_g*/, double /*dt*/,
                                      int /*steps*/) {
  throw legkit::NotImplemented("attitudeErrorFromBias");
}

}  // namespace ex57_2_1
