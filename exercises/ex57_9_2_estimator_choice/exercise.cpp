// Your solution to exercise 57.9.2. Replace the throws with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_9_2.hpp"

namespace ex57_9_2 {

Choice choose(Scenario /*scenario*/) {
  throw legkit::NotImplemented("choose");
}

Drift drift(const legkit::io::Log& /*log*/, const std::string& /*estimator*/) {
  throw legkit::NotImplemented("drift");
}

}  // namespace ex57_9_2
