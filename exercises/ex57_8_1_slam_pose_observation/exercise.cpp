// Your solution to exercise 57.8.1. Replace the throws with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_8_1.hpp"

namespace ex57_8_1 {

Pose mapOdomMeasurement(const PoseMeasurement& /*z*/, const Pose& /*T_OB*/) {
  throw legkit::NotImplemented("mapOdomMeasurement");
}

OdomHistory::OdomHistory(std::size_t capacity) : ring_(capacity) {}

void OdomHistory::push(double /*t*/, const Pose& /*T_OB*/) {
  throw legkit::NotImplemented("OdomHistory::push");
}

Pose OdomHistory::at(double /*t*/) const {
  throw legkit::NotImplemented("OdomHistory::at");
}

}  // namespace ex57_8_1
