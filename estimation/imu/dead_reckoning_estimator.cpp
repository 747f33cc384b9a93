#include "estimation/imu/dead_reckoning_estimator.hpp"

#include "estimation/imu/dead_reckoning.hpp"

namespace legkit::imu {

void DeadReckoningEstimator::reset(const EstimateSample& x0) {
  x_ = {lie::SO3d::fromQuaternion(x0.q), x0.v, x0.p};
  b_g_.setZero();
  t_ = x0.t;
  has_previous_ = false;
  startHealth(x0);
}

void DeadReckoningEstimator::initialise(const InitialState& s) {
  checkInitialState(s, name());
  reset(s.x);
  b_g_ = s.b_g;
}

void DeadReckoningEstimator::step(const StepInput& raw) {
  // Contacts are not used here, but admitted like everywhere, so that health() means the same.
  InputCopies copies;
  const auto [in, imu_admitted] =
      admit(raw, has_previous_, limits_, "DeadReckoningEstimator", copies);
  if (has_previous_ && in.dt > 0.0)
    x_ = deadReckoningStep(x_, previous_, model::ImuBias{b_g_, Eigen::Vector3d::Zero()}, in.dt);
  if (imu_admitted) {
    previous_ = in.imu;
    has_previous_ = true;
  }
  t_ = in.t;
  if (!guard_.check(estimate(), limits_)) recover(in.t);
}

EstimateSample DeadReckoningEstimator::estimate() const {
  return {t_, x_.R.quaternion(), x_.v, x_.p};
}

}  // namespace legkit::imu
