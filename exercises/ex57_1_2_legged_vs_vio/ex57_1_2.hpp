// Exercise 57.1.2: legged state estimation vs phone VIO. A discussion question; the one number
// behind it is how long each system has to coast on its IMU between corrections.
#pragma once

namespace ex57_1_2 {

// Position error [m] that pure IMU integration accumulates over one gap of `gap` seconds
// between corrections, from a constant unknown accelerometer bias b_a [m/s^2], starting from a
// freshly corrected state (zero position and velocity error).
double driftOverGap(double b_a, double gap);

// How many times larger that per-gap drift is for a VIO corrected at camera_hz than for a
// legged estimator corrected by leg kinematics at kinematics_hz (same IMU, same bias).
double gapDriftRatio(double camera_hz, double kinematics_hz);

}  // namespace ex57_1_2
