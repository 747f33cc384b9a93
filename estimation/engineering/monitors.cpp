#include "estimation/engineering/monitors.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace legkit::engineering {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void requirePositive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string("HealthMonitor: ") + name +
                                " must be positive and finite, got " + std::to_string(value));
  }
}

}  // namespace

const char* alarmName(Alarm a) {
  constexpr std::array<const char*, kNumAlarms> names = {
      "IMU dropout",        "stuck encoder",     "force-sensor drift",
      "exteroception lost", "covariance growth", "covariance not positive definite"};
  return names[static_cast<int>(a)];
}

HealthMonitor::HealthMonitor(const MonitorParams& params, int num_feet, double nominal_dt)
    : params_(params), num_feet_(num_feet), nominal_dt_(nominal_dt) {
  if (num_feet < 1 || num_feet > io::kMaxFeet) {
    throw std::invalid_argument("HealthMonitor: num_feet must be in [1, " +
                                std::to_string(io::kMaxFeet) + "], got " +
                                std::to_string(num_feet));
  }
  requirePositive(nominal_dt, "nominal_dt");
  requirePositive(params.imu_dropout_periods, "imu_dropout_periods");
  requirePositive(params.stuck_encoder_time, "stuck_encoder_time");
  requirePositive(params.stuck_encoder_gyro, "stuck_encoder_gyro");
  requirePositive(params.stuck_encoder_speed, "stuck_encoder_speed");
  requirePositive(params.force_drift_window, "force_drift_window");
  requirePositive(params.force_drift_sigma, "force_drift_sigma");
  requirePositive(params.force_sigma, "force_sigma");
  requirePositive(params.exteroception_timeout, "exteroception_timeout");
  requirePositive(params.position_sigma_max, "position_sigma_max");
  requirePositive(params.velocity_sigma_max, "velocity_sigma_max");
  reset();
}

void HealthMonitor::reset() {
  report_ = MonitorReport{};
  report_.since.fill(kNaN);
  report_.first.fill(kNaN);
  report_.last.fill(kNaN);
  t_prev_ = kNaN;
  t_first_ = kNaN;
  q_prev_.setZero();
  dq_prev_.setZero();
  frozen_for_.fill(0.0);
  moved_.fill(false);
  leg_stuck_.fill(false);
  force_bias_.fill(0.0);
  drifting_.fill(false);
  unhealthy_seen_ = 0;
}

void HealthMonitor::set(Alarm a, bool on, double t) {
  const int i = static_cast<int>(a);
  if (on && !report_.active[i]) {
    report_.since[i] = t;
    ++report_.count[i];
    if (std::isnan(report_.first[i])) report_.first[i] = t;
  }
  if (on) report_.last[i] = t;
  if (!on) report_.since[i] = kNaN;
  report_.active[i] = on;
}

const MonitorReport& HealthMonitor::update(const MonitorInput& in) {
  const bool first = std::isnan(t_prev_);
  // A sample not after the previous one (a clock that stepped back) integrates nothing.
  const double dt = first ? 0.0 : std::max(0.0, in.t - t_prev_);
  if (first) t_first_ = in.t;

  // IMU dropout: the interval that ends with this sample is over the bound. The filter held the
  // previous sample across it; the alarm holds from the last sample before the gap until the next
  // on-time sample.
  report_.imu_gap = dt;
  // (A relative 1e-9 over the bound: an interval of exactly the bound, computed from two
  // timestamps, is no dropout.)
  const bool gap = dt > params_.imu_dropout_periods * nominal_dt_ * (1.0 + 1e-9);
  if (gap) {
    set(Alarm::kImuDropout, false, in.t);  // a second gap in a row is a new dropout
    set(Alarm::kImuDropout, true, t_prev_);
    report_.last[static_cast<int>(Alarm::kImuDropout)] = in.t;
  } else {
    set(Alarm::kImuDropout, false, in.t);
  }

  // Stuck encoder: angle bit for bit unchanged and rate zero or unchanged, per joint, while the
  // body moves (its gyro or its estimated speed), for stuck_encoder_time.
  const bool body_moves =
      in.gyro.norm() > params_.stuck_encoder_gyro || in.v_hat.norm() > params_.stuck_encoder_speed;
  const int per_leg = in.num_joints / num_feet_;
  leg_stuck_.fill(false);
  for (int k = 0; k < in.num_joints; ++k) {
    const bool frozen =
        !first && in.q[k] == q_prev_[k] && (in.dq[k] == 0.0 || in.dq[k] == dq_prev_[k]);
    frozen_for_[k] = frozen ? frozen_for_[k] + dt : 0.0;
    moved_[k] = frozen && (moved_[k] || body_moves);
    if (per_leg > 0 && moved_[k] && frozen_for_[k] >= params_.stuck_encoder_time) {
      const int leg = k / per_leg;
      if (leg < num_feet_) leg_stuck_[leg] = true;
    }
  }
  bool any_stuck = false;
  for (int i = 0; i < num_feet_; ++i) any_stuck = any_stuck || leg_stuck_[i];
  set(Alarm::kStuckEncoder, any_stuck, in.t);
  q_prev_ = in.q;
  dq_prev_ = in.dq;

  // Force-sensor drift: exponential mean of (sensor - model) with time constant
  // force_drift_window; on beyond force_drift_sigma sigma, off again below half of it.
  bool any_drift = false;
  if (in.has_force) {
    const double alpha = first ? 0.0 : std::min(1.0, dt / params_.force_drift_window);
    const double on = params_.force_drift_sigma * params_.force_sigma;
    for (int i = 0; i < num_feet_; ++i) {
      const double r = in.force[i] - in.force_model[i];
      if (std::isfinite(r)) force_bias_[i] += alpha * (r - force_bias_[i]);
      const double b = std::abs(force_bias_[i]);
      drifting_[i] = drifting_[i] ? b > 0.5 * on : b > on;
      any_drift = any_drift || drifting_[i];
    }
  }
  set(Alarm::kForceDrift, any_drift, in.t);

  // Exteroception lost: no update for the timeout (counted from the first step when none yet).
  if (in.has_exteroception) {
    const double since = std::isfinite(in.exteroception_t) ? in.exteroception_t : t_first_;
    const bool lost = in.t - since > params_.exteroception_timeout;
    if (lost && !report_[Alarm::kExteroceptionLost]) {
      set(Alarm::kExteroceptionLost, true, since + params_.exteroception_timeout);
    }
    set(Alarm::kExteroceptionLost, lost, in.t);
  } else {
    set(Alarm::kExteroceptionLost, false, in.t);
  }

  // Covariance: the largest position and velocity sigma against their bounds, and LDLT of P
  // (of its (v, p) block when attitude is not a state) with a strictly positive diagonal D.
  bool growth = false, not_pd = false;
  if (in.P != nullptr) {
    const Eigen::Matrix<double, 9, 9>& P = in.P->P;
    report_.velocity_sigma = std::sqrt(P.diagonal().segment<3>(3).maxCoeff());
    report_.position_sigma = std::sqrt(P.diagonal().segment<3>(6).maxCoeff());
    growth = !P.diagonal().allFinite() || !(report_.velocity_sigma <= params_.velocity_sigma_max) ||
             !(report_.position_sigma <= params_.position_sigma_max);
    if (!P.allFinite()) {
      not_pd = true;
    } else if (in.P->has_attitude) {
      const Eigen::LDLT<Eigen::Matrix<double, 9, 9>> ldlt(P);
      not_pd = ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0);
    } else {
      const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(P.bottomRightCorner<6, 6>());
      not_pd = ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0);
    }
  }
  if (in.health != nullptr) {
    const std::uint64_t n = (*in.health)[Fault::kStateUnhealthy];
    not_pd = not_pd || n > unhealthy_seen_;
    unhealthy_seen_ = n;
  }
  set(Alarm::kCovarianceGrowth, growth, in.t);
  set(Alarm::kNotPositiveDefinite, not_pd, in.t);

  report_.uncertain = false;
  for (const bool a : report_.active) report_.uncertain = report_.uncertain || a;
  t_prev_ = in.t;
  return report_;
}

double HealthMonitor::forceNoiseScale(int foot) const {
  if (foot < 0 || foot >= num_feet_ || !drifting_[foot]) return 1.0;
  const double b = force_bias_[foot] / params_.force_sigma;
  return 1.0 + b * b;
}

bool HealthMonitor::legTrusted(int foot) const {
  return foot < 0 || foot >= num_feet_ || !leg_stuck_[foot];
}

int HealthMonitor::applyTo(StepInput& in) const {
  int kept = 0;
  for (int j = 0; j < in.num_contacts; ++j) {
    if (!legTrusted(in.contacts[j].foot)) continue;
    in.contacts[kept] = in.contacts[j];
    in.normal_force[kept] = in.normal_force[j];
    ++kept;
  }
  const int removed = in.num_contacts - kept;
  in.num_contacts = kept;
  return removed;
}

}  // namespace legkit::engineering
