// Your solution to exercise 57.6.2. Replace each throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_6_2.hpp"

namespace ex57_6_2 {

Eigen::Vector4d newtonStep(const Eigen::Vector4d& /*w*/, const std::vector<Eigen::Vector4d>& /*x*/,
                           const std::vector<bool>& /*y*/, double /*l2*/) {
  throw legkit::NotImplemented("newtonStep");
}

LogisticModel trainContactProbability(const std::vector<ContactFeatures>& /*samples*/,
                                      const std::vector<bool>& /*labels*/, double /*l2*/) {
  throw legkit::NotImplemented("trainContactProbability");
}

}  // namespace ex57_6_2
