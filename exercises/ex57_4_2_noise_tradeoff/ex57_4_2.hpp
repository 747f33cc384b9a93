// Exercise 57.4.2: how the linear KF's three noise settings trade bias against variance.
#pragma once

#include "estimation/linear_kf/linear_kf.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/bias_variance.hpp"
#include "io/log.hpp"

namespace ex57_4_2 {

// The three knobs of the exercise, each a factor on a variance (1: the value given).
struct Scales {
  double foot_process_noise = 1.0;  // (a) sigma_f^2, the stance feet's random walk
  double accel_noise = 1.0;         // (b) sigma_a^2, the accelerometer noise of the prediction
  double measurement_noise = 1.0;   // (c) R, every kinematic measurement's covariance
};

// 1. `nominal` with its noise densities (standard deviations) scaled so that each variance is
//    multiplied by its factor: foot_stance_density by (a), imu.accel_noise_density by (b) and
//    the leg-velocity noise foot_velocity_sigma by (c). Every other field stays as it is.
legkit::linear_kf::LinearKfParams filterParams(const Scales& scales,
                                               const legkit::linear_kf::LinearKfParams& nominal);

// 2. The front end's noise (the source of the foot-position R) with its variances multiplied
//    by (c), from `nominal`.
legkit::FrontendNoise frontendNoise(const Scales& scales, const legkit::FrontendNoise& nominal);

// 3. One point of the trade-off curve: the linear KF with filterParams(scales, default params),
//    fed the log through a front end with frontendNoise(scales, nominal), started from the
//    log's ground truth at row 0 (eval::initialState), and its velocity error split into bias
//    and variance over `window` seconds (eval::velocityBiasVariance).
legkit::eval::BiasVariance tradeoffPoint(const legkit::io::Log& log, const Scales& scales,
                                         const legkit::FrontendNoise& nominal, double window);

}  // namespace ex57_4_2
