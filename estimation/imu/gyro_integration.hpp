// Attitude from the gyro (section 57.2): dR/dt = R [w_m - b_g]_x, discretised with the exact
// Rodrigues step for a rate held constant over the step,
//   R_{k+1} = R_k Exp((w_m,k - b_g) dt).
// The step is exact only when the rate is constant within [t_k, t_k + dt]; gyroStepError
// measures what holding it costs when the rate ramps or oscillates inside the step (exercise
// 57.2.3, e.g. a landing impact).
#pragma once

#include <Eigen/Core>
#include <functional>

#include "lie/so3.hpp"

namespace legkit::imu {

// R_{k+1} = R_k Exp((w_m - b_g) dt). Throws std::invalid_argument for dt <= 0 or a NaN input.
lie::SO3d gyroStep(const lie::SO3d& R, const Eigen::Vector3d& w_m, const Eigen::Vector3d& b_g,
                   double dt);

// A true body rate w(t) [rad/s] in the body frame.
using RateProfile = std::function<Eigen::Vector3d(double)>;

// Which value of w(t) one step of length dt holds constant.
enum class RateSample {
  kStart,     // w(t_k): the latest sample, what a 1-sample IMU loop uses
  kMidpoint,  // w(t_k + dt/2): about the step's mean rate, what an integrating IMU reports
};

// Attitude after integrating w over [t0, t0 + T] in `steps` Rodrigues steps from R = I.
lie::SO3d integrateRate(const RateProfile& w, double t0, double T, int steps, RateSample sample);

// Angle [rad] between the attitude after one step of length dt from t0 (rate sampled as
// `sample`) and a reference integration of the same interval with `refinement` midpoint
// substeps: the discretisation error of R_{k+1} = R_k Exp(w_k dt).
double gyroStepError(const RateProfile& w, double t0, double dt, RateSample sample,
                     int refinement = 2000);

}  // namespace legkit::imu
