// Your solution to exercise 57.5.2. Replace each throw with your implementation.
#include "ex57_5_2.hpp"

#include <legkit/not_implemented.hpp>

namespace ex57_5_2 {

Vector9d rightInvariantError(const lie::SE23d& /*X_hat*/, const lie::SE23d& /*X*/) {
  throw legkit::NotImplemented("rightInvariantError");
}

Vector9d errorAfterStep(const lie::SE23d& /*X_hat*/, const lie::SE23d& /*X*/, const ImuInput& /*u*/,
                        const Eigen::Vector3d& /*g*/) {
  throw legkit::NotImplemented("errorAfterStep");
}

Matrix9d errorTransition(const lie::SE23d& /*X*/, const ImuInput& /*u*/,
                         const Eigen::Vector3d& /*g*/, double /*h*/) {
  throw legkit::NotImplemented("errorTransition");
}

Matrix9d eskfErrorTransition(const lie::SE23d& /*X_hat*/, const ImuInput& /*u*/,
                             const Eigen::Vector3d& /*g*/, double /*h*/) {
  throw legkit::NotImplemented("eskfErrorTransition");
}

Matrix9d closedFormPhi(const Eigen::Vector3d& /*g*/, double /*dt*/) {
  throw legkit::NotImplemented("closedFormPhi");
}

}  // namespace ex57_5_2
