// Your solution to exercise 57.3.2. Replace each throw with your implementation.
#include "ex57_3_2.hpp"

#include <legkit/not_implemented.hpp>

namespace ex57_3_2 {

Eigen::MatrixXd stackedJacobian(const Eigen::Vector3d& /*p*/, const Eigen::Matrix3d& /*R*/,
                                const Eigen::Vector3d& /*v*/, const Eigen::Matrix3Xd& /*d*/,
                                bool /*with_gravity*/) {
  throw legkit::NotImplemented("stackedJacobian");
}

NullSpace nullSpace(const Eigen::MatrixXd& /*H*/) {
  throw legkit::NotImplemented("nullSpace");
}

}  // namespace ex57_3_2
