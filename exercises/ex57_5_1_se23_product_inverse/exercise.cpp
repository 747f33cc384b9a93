// Your solution to exercise 57.5.1. Replace each throw with the block formula.
#include "ex57_5_1.hpp"

#include <legkit/not_implemented.hpp>

namespace ex57_5_1 {

Matrix5d toMatrix(const ExtendedPose& /*X*/) { throw legkit::NotImplemented("toMatrix"); }

ExtendedPose compose(const ExtendedPose& /*X1*/, const ExtendedPose& /*X2*/) {
  throw legkit::NotImplemented("compose");
}

ExtendedPose inverse(const ExtendedPose& /*X*/) { throw legkit::NotImplemented("inverse"); }

bool isInSE23(const Matrix5d& /*M*/, double /*tol*/) { throw legkit::NotImplemented("isInSE23"); }

}  // namespace ex57_5_1
