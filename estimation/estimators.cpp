#include "estimation/estimators.hpp"

#include <stdexcept>

#include "estimation/imu/dead_reckoning_estimator.hpp"
#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/invariant/tsif.hpp"
#include "estimation/leg_odometry/leg_odometry_estimator.hpp"
#include "estimation/linear_kf/linear_kf.hpp"
#include "estimation/settings.hpp"

namespace legkit {

std::unique_ptr<Estimator> makeEstimator(const std::string& name) {
  if (name == "imu-dead-reckoning") return std::make_unique<imu::DeadReckoningEstimator>();
  if (name == "leg-odometry") return std::make_unique<leg_odometry::LegOdometryEstimator>();
  if (name == "linear-kf") return std::make_unique<linear_kf::LinearKf>();
  if (name == "eskf") return std::make_unique<invariant::Eskf>();
  if (name == "invariant-ekf") return std::make_unique<invariant::InvariantEkf>();
  if (name == "tsif") return std::make_unique<invariant::Tsif>();
  std::string known;
  for (const std::string& n : estimatorNames()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown estimator '" + name + "' (known: " + known + ")");
}

std::unique_ptr<Estimator> makeEstimator(const std::string& name, const Settings& s) {
  // The block the three filters of section 57.5 share (estimation/invariant/filter_params.hpp).
  invariant::FilterParams family;
  family.imu = s.imu;
  family.foot_stance_density = s.feet.stance_density;
  family.foot_swing_density = s.feet.swing_density;
  family.feet_correct_yaw = s.feet.correct_yaw;
  family.heading_turn_rate = s.feet.heading_turn_rate;
  family.heading_turn_time = s.feet.heading_turn_time;
  family.flat_feet = s.feet.flat;
  family.foot_rotation_stance_density = s.feet.rotation_stance_density;
  family.sigma_attitude = s.priors.sigma_attitude;
  family.sigma_velocity = s.priors.sigma_velocity;
  family.sigma_position = s.priors.sigma_position;
  family.sigma_gyro_bias = s.priors.sigma_gyro_bias;
  family.sigma_accel_bias = s.priors.sigma_accel_bias;
  family.limits = s.limits;
  family.gating = s.gating;
  if (name == "imu-dead-reckoning") return std::make_unique<imu::DeadReckoningEstimator>(s.limits);
  if (name == "leg-odometry") {
    return std::make_unique<leg_odometry::LegOdometryEstimator>(s.limits);
  }
  if (name == "linear-kf") {
    linear_kf::LinearKfParams p;
    p.imu = s.imu;
    p.limits = s.limits;
    p.foot_stance_density = s.feet.stance_density;
    p.foot_swing_density = s.linear_kf.foot_swing_density;
    p.use_leg_velocity = s.linear_kf.use_leg_velocity;
    p.foot_velocity_sigma = s.linear_kf.foot_velocity_sigma;
    p.model_attitude_error = s.linear_kf.model_attitude_error;
    p.attitude_correlation_time = s.linear_kf.attitude_correlation_time;
    p.accel_compensation_time = s.linear_kf.accel_compensation_time;
    p.sigma_position = s.priors.sigma_position;
    p.sigma_velocity = s.priors.sigma_velocity;
    p.foot_init_sigma = s.priors.foot_init_sigma;
    p.attitude.imu = s.imu;
    p.attitude.k_P = s.linear_kf.k_P;
    p.attitude.k_I = s.linear_kf.k_I;
    p.attitude.accel_tolerance = s.linear_kf.accel_tolerance;
    p.attitude.sigma_tilt = s.linear_kf.sigma_tilt;
    p.attitude.sigma_yaw = s.linear_kf.sigma_yaw;
    p.attitude.sigma_gyro_bias = s.priors.sigma_gyro_bias;
    p.gating = s.gating;
    return std::make_unique<linear_kf::LinearKf>(p);
  }
  if (name == "eskf") {
    return std::make_unique<invariant::Eskf>(
        invariant::EskfParams{family, s.priors.foot_init_sigma});
  }
  if (name == "invariant-ekf") {
    return std::make_unique<invariant::InvariantEkf>(invariant::InvariantEkfParams{
        family, s.invariant_ekf.discretisation, s.invariant_ekf.touchdown_attitude});
  }
  if (name == "tsif") {
    return std::make_unique<invariant::Tsif>(
        invariant::TsifParams{family, s.priors.foot_init_sigma, s.tsif.iterations});
  }
  return makeEstimator(name);  // throws, listing the known names
}

}  // namespace legkit
