// Your solution to exercise 57.2.2. Replace each throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_2_2.hpp"

namespace ex57_2_2 {

Eigen::Matrix3d rotationFromRpy(const Eigen::Vector3d& /*rpy*/) {
  throw legkit::NotImplemented("rotationFromRpy");
}

Eigen::Vector3d accelerometerAtRest(const Eigen::Vector3d& /*rpy*/) {
  throw legkit::NotImplemented("accelerometerAtRest");
}

Eigen::Vector3d magnetometer(const Eigen::Vector3d& /*rpy*/, const Eigen::Vector3d& /*m_world*/) {
  throw legkit::NotImplemented("magnetometer");
}

Eigen::Matrix3d measurementJacobian(int /*which*/, const Eigen::Vector3d& /*rpy*/,
                                    const Eigen::Vector3d& /*m_world*/) {
  throw legkit::NotImplemented("measurementJacobian");
}

double headingErrorFromDisturbance(const Eigen::Vector3d& /*m_world*/,
                                   const Eigen::Vector3d& /*disturbance*/) {
  throw legkit::NotImplemented("headingErrorFromDisturbance");
}

}  // namespace ex57_2_2
