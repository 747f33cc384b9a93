// Your solution to exercise 57.5.3. Replace each throw with your implementation.
#include "ex57_5_3.hpp"

#include <legkit/not_implemented.hpp>

namespace ex57_5_3 {

Matrix15 eskfF(const NavState& /*x_hat*/, const Eigen::Vector3d& /*w_m*/,
               const Eigen::Vector3d& /*a_m*/) {
  throw legkit::NotImplemented("eskfF");
}

Matrix15 inekfA(const NavState& /*x_hat*/, const Eigen::Vector3d& /*g*/) {
  throw legkit::NotImplemented("inekfA");
}

BlockCount countBlocks(const Matrix15& /*J_at_x1*/, const Matrix15& /*J_at_x2*/) {
  throw legkit::NotImplemented("countBlocks");
}

}  // namespace ex57_5_3
