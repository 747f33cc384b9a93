// Your solution to exercise 57.4.3. Replace each throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_4_3.hpp"

namespace ex57_4_3 {

Eigen::Matrix2d navigationNoisePerAxis(double /*dt*/, double /*accel_density*/) {
  throw legkit::NotImplemented("navigationNoisePerAxis");
}

Matrix18 predictCovariance(const Matrix18& /*P*/, double /*dt*/) {
  throw legkit::NotImplemented("predictCovariance");
}

Matrix18 josephUpdate(const Matrix18& /*P*/, const Matrix18x3& /*K*/, int /*foot*/,
                      const Eigen::Matrix3d& /*Rn*/) {
  throw legkit::NotImplemented("josephUpdate");
}

Eigen::Vector3d centroidVelocity(const Eigen::Matrix3d& /*R*/, const Eigen::Vector3d& /*w_b*/,
                                 const std::vector<legkit::ContactMeasurement>& /*stance*/) {
  throw legkit::NotImplemented("centroidVelocity");
}

}  // namespace ex57_4_3
