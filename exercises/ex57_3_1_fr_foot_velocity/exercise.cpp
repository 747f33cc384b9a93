// Your solution to exercise 57.3.1. Replace each throw with the explicit expressions.
#include "ex57_3_1.hpp"

#include <legkit/not_implemented.hpp>

namespace ex57_3_1 {

Eigen::Vector3d frFootPosition(const Eigen::Vector3d& /*q*/) {
  throw legkit::NotImplemented("frFootPosition");
}

Eigen::Matrix3d frFootJacobian(const Eigen::Vector3d& /*q*/) {
  throw legkit::NotImplemented("frFootJacobian");
}

Eigen::Vector3d frBaseVelocityBody(const Eigen::Vector3d& /*w*/, const Eigen::Vector3d& /*q*/,
                                   const Eigen::Vector3d& /*dq*/) {
  throw legkit::NotImplemented("frBaseVelocityBody");
}

}  // namespace ex57_3_1
