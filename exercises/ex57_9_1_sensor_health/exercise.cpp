// Your solution to exercise 57.9.1. Replace the throws with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_9_1.hpp"

namespace ex57_9_1 {

Response responseTo(Fault /*fault*/) {
  throw legkit::NotImplemented("responseTo");
}

Thresholds defaultThresholds() {
  throw legkit::NotImplemented("defaultThresholds");
}

SensorMonitor::SensorMonitor(const Thresholds& thresholds) : th_(thresholds) {}

const Report& SensorMonitor::update(const legkit::io::LogRow& /*row*/) {
  throw legkit::NotImplemented("SensorMonitor::update");
}

}  // namespace ex57_9_1
