// Reference solution to exercise 57.1.1.
#include <cmath>

#include "ex57_1_1.hpp"

namespace ex57_1_1 {

// The bias is integrated twice: dv = b_a t, dp = b_a t^2 / 2.
double positionDriftFromAccelBias(double b_a, double t) {
  return 0.5 * std::abs(b_a) * t * t;
}

// The bias is integrated once: dtheta = b_g t, converted to degrees.
double attitudeDriftDegFromGyroBias(double b_g, double t) {
  return std::abs(b_g) * t * 180.0 / M_PI;
}

// A tilt theta(t) = b_g t leaves g sin(theta) ~ g b_g t of gravity in the horizontal
// acceleration; integrating twice gives g b_g t^3 / 6.
double positionDriftFromGyroBias(double b_g, double t) {
  return 9.81 * std::abs(b_g) * t * t * t / 6.0;
}

}  // namespace ex57_1_1
