// Exercise 57.2.3: the error of the discrete gyro step R_{k+1} = R_k Exp(w_k dt) when the rate
// changes within the step (a landing impact).
#pragma once

#include <Eigen/Core>
#include <functional>

namespace ex57_2_3 {

// A body rate w(t) [rad/s], t in seconds from the start of the step.
using Rate = std::function<Eigen::Vector3d(double)>;

// Angle [rad] between one step R = Exp(w(0) dt) (the rate sampled at the start of the step and
// held) and the true attitude after dt, obtained by integrating dR/dt = R [w(t)]_x from R = I
// accurately (to better than 1e-3 of the answer).
double oneStepError(const Rate& w, double dt);

// Leading term of that error for a ramp w(t) = w0 + alpha t, from your derivation.
double predictedRampError(const Eigen::Vector3d& w0, const Eigen::Vector3d& alpha, double dt);

// The longest step dt [s] for which a ramp of angular acceleration |alpha| [rad/s^2] keeps the
// one-step error (leading term) at or below tol [rad].
double maxStepForTolerance(double alpha, double tol);

}  // namespace ex57_2_3
