#include "estimation/imu/gyro_integration.hpp"

#include <stdexcept>

#include "estimation/imu/input_checks.hpp"

namespace legkit::imu {

lie::SO3d gyroStep(const lie::SO3d& R, const Eigen::Vector3d& w_m, const Eigen::Vector3d& b_g,
                   double dt) {
  detail::requirePositiveStep(dt, "gyroStep");
  detail::requireFinite(w_m, "gyroStep", "gyro reading w_m");
  detail::requireFinite(b_g, "gyroStep", "gyro bias b_g");
  // R_{k+1} = R_k Exp((w_m - b_g) dt), re-orthonormalised through the unit quaternion.
  const Eigen::Matrix3d R_next = R.matrix() * lie::SO3d::Exp((w_m - b_g) * dt).matrix();
  return lie::SO3d::fromQuaternion(Eigen::Quaterniond(R_next));
}

lie::SO3d integrateRate(const RateProfile& w, double t0, double T, int steps, RateSample sample) {
  detail::requirePositiveStep(T, "integrateRate");
  if (steps < 1) throw std::invalid_argument("integrateRate: steps must be at least 1");
  const double dt = T / steps;
  const double offset = sample == RateSample::kStart ? 0.0 : 0.5 * dt;
  lie::SO3d R;
  for (int k = 0; k < steps; ++k) {
    const Eigen::Vector3d w_k = w(t0 + k * dt + offset);
    detail::requireFinite(w_k, "integrateRate", "rate w(t)");
    R = R * lie::SO3d::Exp(w_k * dt);
  }
  return R.normalized();
}

double gyroStepError(const RateProfile& w, double t0, double dt, RateSample sample,
                     int refinement) {
  const lie::SO3d R_step = integrateRate(w, t0, dt, 1, sample);
  const lie::SO3d R_ref = integrateRate(w, t0, dt, refinement, RateSample::kMidpoint);
  return R_step.rminus(R_ref).norm();  // |Log(R_ref^T R_step)|
}

}  // namespace legkit::imu
