// Your solution to exercise 57.4.1. Replace each throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_4_1.hpp"

namespace ex57_4_1 {

Matrix18 F(double /*dt*/) {
  throw legkit::NotImplemented("F");
}

Eigen::Matrix<double, kDim, 3> B(double /*dt*/) {
  throw legkit::NotImplemented("B");
}

Matrix18 Q(double /*dt*/, const Stance& /*stance*/, const Densities& /*densities*/) {
  throw legkit::NotImplemented("Q");
}

Eigen::MatrixXd H(const Stance& /*stance*/) {
  throw legkit::NotImplemented("H");
}

Eigen::MatrixXd R(const Stance& /*stance*/, const Eigen::Matrix3d& /*R_hat*/,
                  const std::array<Eigen::Vector3d, 4>& /*r*/,
                  const std::array<Eigen::Matrix3d, 4>& /*C*/,
                  const Eigen::Matrix3d& /*Sigma_theta*/) {
  throw legkit::NotImplemented("R");
}

}  // namespace ex57_4_1
