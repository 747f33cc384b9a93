// Exercise 57.1.1: how far pure IMU integration drifts in 30 s.
#pragma once

namespace ex57_1_1 {

// (a) Position error [m] after t seconds of dead reckoning when the accelerometer has a
// constant bias b_a [m/s^2] that the integrator does not know (attitude assumed perfect).
double positionDriftFromAccelBias(double b_a, double t);

// (b) Attitude error [deg] after t seconds when the gyro has a constant bias b_g [rad/s].
double attitudeDriftDegFromGyroBias(double b_g, double t);

// (c) Position error [m] after t seconds caused by the gyro bias alone, for a robot standing
// level and a bias about a horizontal axis: the wrongly tilted attitude leaves part of gravity
// in the "acceleration". Use the small-angle approximation.
double positionDriftFromGyroBias(double b_g, double t);

}  // namespace ex57_1_1
