// Your solution to exercise 57.2.3. Replace each throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_2_3.hpp"

namespace ex57_2_3 {

double oneStepError(const Rate& /*w*/, double /*dt*/) {
  throw legkit::NotImplemented("oneStepError");
}

double predictedRampError(const Eigen::Vector3d& /*w0*/, const Eigen::Vector3d& /*alpha*/,
                          double /*dt*/) {
  throw legkit::NotImplemented("predictedRampError");
}

double maxStepForTolerance(double /*alpha*/, double /*tol*/) {
  throw legkit::NotImplemented("maxStepForTolerance");
}

}  // namespace ex57_2_3
