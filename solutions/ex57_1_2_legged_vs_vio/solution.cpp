// Reference solution to exercise 57.1.2.
#include <cmath>

#include "ex57_1_2.hpp"

namespace ex57_1_2 {

// From a corrected state the bias is integrated twice over the gap: b_a gap^2 / 2.
double driftOverGap(double b_a, double gap) {
  return 0.5 * std::abs(b_a) * gap * gap;
}

// The drift per gap goes with gap^2, and gap = 1 / rate.
double gapDriftRatio(double camera_hz, double kinematics_hz) {
  const double r = kinematics_hz / camera_hz;
  return r * r;
}

}  // namespace ex57_1_2
