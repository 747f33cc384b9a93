// Your solution to exercise 57.1.1. Replace each throw with a formula.
#include <legkit/not_implemented.hpp>

#include "ex57_1_1.hpp"

namespace ex57_1_1 {

double positionDriftFromAccelBias(double /*b_a*/, double /*t*/) {
  throw legkit::NotImplemented("positionDriftFromAccelBias");
}

double attitudeDriftDegFromGyroBias(double /*b_g*/, double /*t*/) {
  throw legkit::NotImplemented("attitudeDriftDegFromGyroBias");
}

double positionDriftFromGyroBias(double /*b_g*/, double /*t*/) {
  throw legkit::NotImplemented("positionDriftFromGyroBias");
}

}  // namespace ex57_1_1
