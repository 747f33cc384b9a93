#include "estimation/state_estimator.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "estimation/estimators.hpp"
#include "estimation/imu_extrinsic_frames.hpp"
#include "model/mujoco_kinematics.hpp"

namespace legkit {
namespace {

// The legs of settings.robot: null for the built-in quadruped (no model), else its model file's
// (model::makeLegKinematics, whose errors are std::runtime_error naming the file).
std::unique_ptr<model::LegKinematics> robotLegs(const RobotSettings& r) {
  if (r.model.empty()) return nullptr;
  return model::makeLegKinematics(r.model, r.base, r.feet, r.joints);
}

// The columns the manager's samples fill: the quadruped's joints (or the robot's generic joints),
// forces, and the robot's flags when they are the contact source.
io::LogLayout managerLayout(const Settings& s, const model::LegKinematics* legs) {
  io::LogLayout layout;
  if (legs) {
    layout.joints = false;
    layout.num_joints = legs->numJoints();
    layout.num_feet = legs->numFeet();
  }
  layout.force = true;
  layout.contact = s.pipeline.contact == "truth";
  return layout;
}

// The front end: feet into the IMU frame of settings.imu_extrinsic, through the robot's legs.
LogFrontend frontendOf(const io::LogLayout& layout, const model::LegKinematics* legs,
                       const Settings& s) {
  const FrontendNoise noise = frontendNoise(s);
  return legs ? LogFrontend(layout, *legs, noise, s.imu_extrinsic)
              : LogFrontend(layout, model::QuadrupedKinematics(), noise, s.imu_extrinsic);
}

// What the detectors know of the robot (detectorContext), and the settings' planned gait
// (contact.gait) for detector gait-clock, as `legkit run` gives a recorded log.
contact::DetectorContext robotContext(const Settings& s, const model::LegKinematics* legs,
                                      int num_feet) {
  contact::DetectorContext context = detectorContext(s, robotMass(s, legs), num_feet);
  context.gait = gaitSchedule(s, num_feet);
  return context;
}

std::string filterName(const Settings& s) {
  return s.estimators.empty() ? std::string("invariant-ekf") : s.estimators.front();
}

[[noreturn]] void bad(double t, const std::string& what) {
  std::ostringstream os;
  os.precision(17);
  os << "StateEstimator::update at t = " << t << " s: " << what << "; nothing changed";
  throw std::invalid_argument(os.str());
}

// The attitude at rest with yaw 0 whose measured specific force a (-R^T g at rest: world up seen
// from the body) points to world up.
// The attitude whose roll and pitch put the measured specific force a on world up (yaw 0); level
// when a is zero (free fall, or a dead sensor: no direction to take).
Eigen::Quaterniond tiltFrom(const Eigen::Vector3d& a) {
  if (!(a.norm() > 0.0)) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond::FromTwoVectors(a.normalized(), Eigen::Vector3d::UnitZ());
}

}  // namespace

const char* startModeName(StartMode mode) {
  switch (mode) {
    case StartMode::kNotStarted:
      return "not started";
    case StartMode::kGiven:
      return "given";
    case StartMode::kStillWindow:
      return "still window";
    case StartMode::kGaveUp:
      return "gave up: tilt from the last samples";
    case StartMode::kFirstSample:
      return "first sample: tilt from its accelerometer";
  }
  return "?";
}

StateEstimator::StateEstimator(const Settings& settings, std::size_t history, double imu_period)
    : legs_(robotLegs(settings.robot)),
      layout_(managerLayout(settings, legs_.get())),
      extrinsic_(settings.imu_extrinsic),
      estimator_(makeEstimator(filterName(settings), settings)),
      pipeline_(frontendOf(layout_, legs_.get(), settings), settings.pipeline,
                robotContext(settings, legs_.get(), layout_.num_feet)),
      init_params_(settings.initialisation),
      init_(settings.initialisation),
      monitor_(settings.monitors, layout_.num_feet, imu_period),
      ring_(history) {
  if (history == 0) throw std::invalid_argument("StateEstimator: history must be at least 1");
  reset();
}

void StateEstimator::reset() {
  start_.reset();
  acc_lowpass_.setZero();
  running_ = false;
  init_.reset();
  monitor_.reset();
  pipeline_.reset();
  row_ = io::LogRow{};
  out_ = EstimatorOutput{};
  last_t_.reset();
  head_ = 0;
  count_ = 0;
}

void StateEstimator::reset(const EstimateSample& x0) {
  reset();
  start_ = x0;
}

void StateEstimator::check(const ImuSample& imu, const JointSample& joints,
                           const ForceSample& forces) const {
  if (!std::isfinite(imu.t)) bad(imu.t, "imu.t is not finite");
  if (last_t_ && !(imu.t > *last_t_)) {
    std::ostringstream os;
    os.precision(17);
    os << "imu.t is not after the previous sample's " << *last_t_ << " s";
    bad(imu.t, os.str());
  }
  if (!imu.gyro.allFinite()) bad(imu.t, "imu.gyro is not finite");
  if (!imu.acc.allFinite()) bad(imu.t, "imu.acc is not finite");
  if (joints.valid) {
    if (joints.count != numJoints()) {
      bad(imu.t, "joints.count is " + std::to_string(joints.count) + ", the robot has " +
                     std::to_string(numJoints()) + " joints");
    }
    for (int j = 0; j < joints.count; ++j) {
      if (!std::isfinite(joints.q[j]))
        bad(imu.t, "joints.q[" + std::to_string(j) + "] is not finite");
      if (!std::isfinite(joints.dq[j])) {
        bad(imu.t, "joints.dq[" + std::to_string(j) + "] is not finite");
      }
    }
  }
  if (forces.valid) {
    for (int f = 0; f < layout_.num_feet; ++f) {
      if (!std::isfinite(forces.force[f])) {
        bad(imu.t, "forces.force[" + std::to_string(f) + "] is not finite");
      }
    }
  }
}

const EstimatorOutput& StateEstimator::update(const ImuSample& imu, const JointSample& joints,
                                              const ForceSample& forces) {
  check(imu, joints, forces);
  if (!running_ && !start_ && init_params_.enabled && !init_.gaveUp()) {
    // First-order low pass over one block of the window: a = a + (dt / (tau + dt)) (a_m - a).
    const double tau = init_params_.duration / engineering::StationaryInitialiser::kBlocks;
    const double dt = last_t_ ? imu.t - *last_t_ : 0.0;
    acc_lowpass_ = last_t_
                       ? Eigen::Vector3d(acc_lowpass_ + dt / (tau + dt) * (imu.acc - acc_lowpass_))
                       : imu.acc;
    if (!init_.add(imu.t, {imu.gyro, imu.acc}) && !init_.gaveUp()) {
      last_t_ = imu.t;  // still waiting for a still window
      out_.x = EstimateSample{};
      out_.x.t = imu.t;
      out_.initialising = true;
      out_.joints_valid = joints.valid;
      out_.forces_valid = forces.valid;
      return out_;
    }
  }
  const bool first = !running_;
  const double dt = first ? 0.0 : imu.t - *last_t_;

  row_.t = imu.t;
  row_.gyro = imu.gyro;
  row_.acc = imu.acc;
  if (joints.valid && legs_) {
    row_.joint_q = joints.q;
    row_.joint_dq = joints.dq;
  } else if (joints.valid) {
    row_.q = joints.q.head<io::kNumJoints>();
    row_.dq = joints.dq.head<io::kNumJoints>();
  } else {
    row_.dq.setZero();  // the last valid angles, held still
    row_.joint_dq.setZero();
  }
  for (int f = 0; f < layout_.num_feet; ++f) {
    row_.force[f] = forces.valid ? forces.force[f] : std::numeric_limits<double>::quiet_NaN();
    row_.contact[f] = forces.contact[f];
  }

  if (first) {
    if (init_.ready() && !start_) {
      InitialState s = init_.result();  // roll, pitch and gyro bias of the still window
      s.x.t = imu.t;
      estimator_->initialise(s);
      out_.start = StartMode::kStillWindow;
    } else {
      EstimateSample x0;
      if (start_) {
        // Given at the base: the filter's body is the IMU (base-frame rate R_BI w_I).
        x0 = extrinsic_.isIdentity() ? *start_
                                     : imuFromBase(extrinsic_, *start_, extrinsic_.q_BI * imu.gyro);
        out_.start = StartMode::kGiven;
      } else if (init_.gaveUp()) {
        x0.q = tiltFrom(acc_lowpass_);
        out_.start = StartMode::kGaveUp;
      } else {
        x0.q = tiltFrom(imu.acc);
        out_.start = StartMode::kFirstSample;
      }
      x0.t = imu.t;
      estimator_->reset(x0);
    }
    running_ = true;
  }

  const StepInput& piped =
      pipeline_.step(row_, dt, estimator_->estimate(), estimator_->covariance());
  // The IMU alone when the encoders gave nothing; without the legs a monitor found stuck.
  bool all_trusted = true;
  for (int f = 0; f < layout_.num_feet; ++f) all_trusted = all_trusted && monitor_.legTrusted(f);
  if (joints.valid && all_trusted) {
    estimator_->step(piped);
  } else {
    trimmed_ = piped;
    if (joints.valid) {
      monitor_.applyTo(trimmed_);
    } else {
      trimmed_.num_contacts = 0;
    }
    estimator_->step(trimmed_);
  }
  last_t_ = imu.t;

  // The filter's IMU state moved back to the base at the sample's measured rate.
  const EstimateSample& x_I = estimator_->estimate();
  const bool mounted =
      !extrinsic_.isIdentity();  // else base = IMU, the filter's numbers as they are
  out_.x = mounted ? baseFromImu(extrinsic_, x_I, imu.gyro) : x_I;
  const std::optional<BaseCovariance> P = estimator_->covariance();
  out_.has_covariance = P.has_value();
  if (P) out_.P = mounted ? baseCovarianceFromImu(extrinsic_, x_I, imu.gyro, *P) : *P;
  out_.contacts = pipeline_.contacts();
  out_.health = estimator_->health();
  const Health& silence = pipeline_.health();
  for (int f = 0; f < static_cast<int>(Fault::kCount); ++f)
    out_.health.count[f] += silence.count[f];
  if (silence.total() > 0 && (out_.health.last_fault == Fault::kCount ||
                              silence.last_fault_t >= out_.health.last_fault_t)) {
    out_.health.last_fault = silence.last_fault;
    out_.health.last_fault_t = silence.last_fault_t;
  }
  out_.initialised = true;
  out_.initialising = false;
  engineering::MonitorInput m;
  m.t = imu.t;
  m.gyro = imu.gyro;
  m.num_joints = numJoints();
  if (legs_) {
    m.q = row_.joint_q;
    m.dq = row_.joint_dq;
  } else {
    m.q.head<io::kNumJoints>() = row_.q;
    m.dq.head<io::kNumJoints>() = row_.dq;
  }
  m.has_force = forces.valid;
  for (int f = 0; f < layout_.num_feet; ++f) {
    m.force[f] = row_.force[f];
    m.force_model[f] = std::numeric_limits<double>::quiet_NaN();  // no torques: no force model
  }
  m.v_hat = out_.x.v;
  m.P = out_.has_covariance ? &out_.P : nullptr;
  m.health = &out_.health;
  out_.monitors = monitor_.update(m);
  out_.joints_valid = joints.valid;
  out_.forces_valid = forces.valid;

  ring_[head_] = out_.x;
  head_ = (head_ + 1) % ring_.size();
  if (count_ < ring_.size()) ++count_;
  return out_;
}

const EstimateSample& StateEstimator::past(std::size_t k) const {
  return ring_[(head_ + ring_.size() - 1 - k) % ring_.size()];
}

double StateEstimator::oldestTime() const {
  return count_ == 0 ? std::numeric_limits<double>::quiet_NaN() : past(count_ - 1).t;
}

StateQuery StateEstimator::stateAt(double t, bool nearest) const {
  if (!std::isfinite(t)) throw std::invalid_argument("StateEstimator::stateAt: t is not finite");
  if (count_ == 0) {
    throw std::out_of_range("StateEstimator::stateAt: no state yet (no update since the start)");
  }
  const EstimateSample& newest = past(0);
  if (t >= newest.t) return {newest, t - newest.t, false};
  if (t < oldestTime()) {
    std::ostringstream os;
    os.precision(17);
    os << "StateEstimator::stateAt: t = " << t << " s is before the oldest buffered state ("
       << oldestTime() << " s)";
    throw std::out_of_range(os.str());
  }
  // Binary search for the newest state at or before t: k (places back) with
  // past(k).t <= t < past(k - 1).t; past(count_ - 1).t <= t < past(0).t holds.
  std::size_t lo = 1, hi = count_ - 1;  // past(hi).t <= t, and the answer is in [lo, hi]
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (past(mid).t <= t) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  const EstimateSample& a = past(lo);      // a.t <= t
  const EstimateSample& b = past(lo - 1);  // t < b.t
  if (nearest) {
    const EstimateSample& n = (t - a.t <= b.t - t) ? a : b;
    return {n, t - n.t, false};
  }
  if (t == a.t) return {a, 0.0, false};
  // s in (0, 1): p and v linear, the attitude on the geodesic between the two (slerp).
  const double s = (t - a.t) / (b.t - a.t);
  EstimateSample x;
  x.t = t;
  x.q = a.q.slerp(s, b.q);
  x.v = a.v + s * (b.v - a.v);
  x.p = a.p + s * (b.p - a.p);
  return {x, 0.0, true};
}

}  // namespace legkit
