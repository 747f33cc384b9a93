// Exercise 57.2.1: attitude error from a pure gyro bias, integrated step by step on SO(3).
#pragma once

#include <Eigen/Core>

namespace ex57_2_1 {

// One gyro integration step R_{k+1} = R_k Exp(w dt) with the exact Rodrigues formula.
// Throws std::invalid_argument if dt <= 0.
Eigen::Matrix3d rodriguesStep(const Eigen::Matrix3d& R, const Eigen::Vector3d& w, double dt);

// The robot does not rotate (true rate 0) but the gyro reads a constant bias b_g, which the
// integrator does not remove. Starting from R = I, integrate `steps` steps of length dt and
// return the final attitude error as an axis-angle (rotation) vector: angle * unit axis.
Eigen::Vector3d attitudeErrorFromBias(const Eigen::Vector3d& b_g, double dt, int steps);

}  // namespace ex57_2_1
