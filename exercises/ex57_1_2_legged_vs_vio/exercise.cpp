// Your solution to exercise 57.1.2. Replace each throw with a formula.
#include <legkit/not_implemented.hpp>

#include "ex57_1_2.hpp"

namespace ex57_1_2 {

double driftOverGap(double /*b_a*/, double /*gap*/) {
  throw legkit::NotImplemented("driftOverGap");
}

double gapDriftRatio(double /*camera_hz*/, double /*kinematics_hz*/) {
  throw legkit::NotImplemented("gapDriftRatio");
}

}  // namespace ex57_1_2
