// Reference solution of exercise 57.4.2.
#include <cmath>

#include "eval/runner.hpp"
#include "ex57_4_2.hpp"
#include "model/quadruped.hpp"

namespace ex57_4_2 {

// A variance scales as the square of its standard deviation or density.
legkit::linear_kf::LinearKfParams filterParams(const Scales& scales,
                                               const legkit::linear_kf::LinearKfParams& nominal) {
  legkit::linear_kf::LinearKfParams p = nominal;
  p.foot_stance_density *= std::sqrt(scales.foot_process_noise);  // sigma_f^2 in Q
  p.imu.accel_noise_density *= std::sqrt(scales.accel_noise);     // sigma_a^2 in Q
  p.foot_velocity_sigma *= std::sqrt(scales.measurement_noise);   // the velocity rows of R
  return p;
}

// R_i = R_hat (J Sigma_q J^T + sigma_c^2 I) R_hat^T: both terms scale with their variance.
legkit::FrontendNoise frontendNoise(const Scales& scales, const legkit::FrontendNoise& nominal) {
  const double k = std::sqrt(scales.measurement_noise);
  return {nominal.encoder_angle_sigma * k, nominal.foot_point_sigma * k};
}

legkit::eval::BiasVariance tradeoffPoint(const legkit::io::Log& log, const Scales& scales,
                                         const legkit::FrontendNoise& nominal, double window) {
  legkit::linear_kf::LinearKf filter(filterParams(scales, {}));
  const legkit::LogFrontend frontend(log.layout, legkit::model::QuadrupedKinematics(),
                                     frontendNoise(scales, nominal));
  const legkit::eval::RunResult run =
      legkit::eval::runOnLog(filter, log, frontend, legkit::eval::initialState(log));
  return legkit::eval::velocityBiasVariance(log, run.trajectory, window);
}

}  // namespace ex57_4_2
