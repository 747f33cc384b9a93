// Your solution to exercise 57.6.3. Replace each throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_6_3.hpp"

namespace ex57_6_3 {

legkit::io::Log delayContacts(const legkit::io::Log& /*log*/, const DetectionDelay& /*delay*/) {
  throw legkit::NotImplemented("delayContacts");
}

double positionRmse(const legkit::io::Log& /*log*/) {
  throw legkit::NotImplemented("positionRmse");
}

DelayCost delayCost(const legkit::io::Log& /*log*/, const DetectionDelay& /*delay*/) {
  throw legkit::NotImplemented("delayCost");
}

}  // namespace ex57_6_3
