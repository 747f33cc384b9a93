#include "estimation/leg_odometry/leg_odometry_estimator.hpp"

#include <stdexcept>
#include <string>

#include "estimation/leg_odometry/velocity_fusion.hpp"

namespace legkit::leg_odometry {

void LegOdometryEstimator::reset(const EstimateSample& x0) {
  R_ = lie::SO3d::fromQuaternion(x0.q);
  b_g_.setZero();
  v_ = x0.v;
  p_ = x0.p;
  t_ = x0.t;
  has_previous_ = false;
  startHealth(x0);
}

void LegOdometryEstimator::initialise(const InitialState& s) {
  checkInitialState(s, name());
  reset(s.x);
  b_g_ = s.b_g;
}

void LegOdometryEstimator::step(const StepInput& raw) {
  // Legs without a velocity would leave the IMU alone: dead reckoning under this estimator's
  // name. Refused, before anything changes, except at a first sample (x0 gives the velocity).
  if (has_previous_) {
    for (const ContactMeasurement& c : raw.stance()) {
      if (c.v_body) continue;
      throw std::invalid_argument(
          "LegOdometryEstimator: at t = " + std::to_string(raw.t) + " stance foot " +
          std::to_string(c.foot) +
          " has no velocity (v_body): leg odometry has nothing to measure (a log of foot "
          "positions needs foot<k>_vx columns or the front end's FootVelocityDifferentiator)");
    }
  }
  InputCopies copies;
  const auto [in, imu_admitted] =
      admit(raw, has_previous_, limits_, "LegOdometryEstimator", copies);
  const Eigen::Vector3d v_before = v_;
  if (has_previous_ && in.dt > 0.0) {
    const Eigen::Vector3d a_world = R_ * previous_.a_m + model::gravity();
    R_ = R_ * lie::SO3d::Exp((previous_.w_m - b_g_) * in.dt);  // R_{k+1} = R_k Exp(w dt)
    v_ += a_world * in.dt;                                     // flight: the IMU alone
  }
  bool legs_measure_velocity = in.num_contacts > 0 && (imu_admitted || has_previous_);
  for (const ContactMeasurement& c : in.stance()) legs_measure_velocity &= c.v_body.has_value();
  if (legs_measure_velocity) {
    const Eigen::Vector3d w = (imu_admitted ? in.imu.w_m : previous_.w_m) - b_g_;
    v_ = meanVelocity(R_.matrix(), w, in.stance());
  }
  if (has_previous_) p_ += 0.5 * (v_before + v_) * in.dt;
  if (imu_admitted) {
    previous_ = in.imu;
    has_previous_ = true;
  }
  t_ = in.t;
  if (!guard_.check(estimate(), limits_)) recover(in.t);
}

EstimateSample LegOdometryEstimator::estimate() const {
  return {t_, R_.quaternion(), v_, p_};
}

}  // namespace legkit::leg_odometry
