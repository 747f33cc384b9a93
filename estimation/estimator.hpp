// The one interface every estimator of the kit implements, so that the evaluation harness, the
// command line and the estimator manager run any of them on the same log.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "estimation/estimate.hpp"
#include "estimation/foot_slots.hpp"
#include "estimation/health.hpp"
#include "estimation/health_guard.hpp"
#include "estimation/step_input.hpp"

namespace legkit {

// The uncertainty an estimator claims for its base state, in one convention shared by every
// filter so that NEES and 3-sigma bounds mean the same thing for all of them:
//   e = (dtheta, dv, dp),  R = Exp(dtheta) R_hat,  v = v_hat + dv,  p = p_hat + dp
// (attitude error in the world frame, then world velocity and position errors). A filter whose
// own error is defined differently (the InEKF's right-invariant xi, the ESKF's body-frame angle)
// maps its covariance into this one to first order.
struct BaseCovariance {
  Eigen::Matrix<double, 9, 9> P = Eigen::Matrix<double, 9, 9>::Identity();
  // False when attitude is an input, not a state (the linear KF): then only the (dv, dp) block,
  // rows and columns 3..8, is meaningful and NEES has 6 degrees of freedom instead of 9.
  bool has_attitude = true;
};

// How well a filter's stance-foot measurements fit the covariance it predicts for them, over a
// run (issue 22 item 3): normalised innovations squared NIS = r^T S^-1 r (r an innovation, S = H
// P H^T + Cov its covariance), each added with its dimension; in `legkit run`'s filters over
// windows of a foot's stance (innovation_windows.hpp: why not per sample). For a consistent filter
// each is chi-square with that many degrees of freedom, so the mean per dimension,
// nis / dimensions, is about 1; far above it the filter is over-confident, far below over-cautious.
// Counted only for feet the filter was told are in stance, p_c >= kNisMinProbability: a foot at a
// lower p_c (touchdown settling, an unsure detector) comes with a covariance that says "mostly
// ignore me", and its NIS says nothing about the stance settings. A touchdown, which only places
// the foot, and a gated foot are no update. What each filter counts: its stanceInnovations()
// (eskf.hpp, invariant_ekf.hpp, linear_kf.hpp). Not the TSIF: its residuals at the prediction
// need the prediction's 27 x 27 marginal, which more than doubled its step (55 -> 140 us).
struct InnovationStats {
  long updates = 0;     // NIS values added (a window, a stacked update)
  long dimensions = 0;  // the sum of their dimensions (3 per foot)
  double nis = 0.0;     // the sum of their r^T S^-1 r

  void add(double d2, int dimension) {
    ++updates;
    dimensions += dimension;
    nis += d2;
  }
  // nis / dimensions (about 1 when consistent); NaN before the first update.
  double meanPerDimension() const {
    return dimensions > 0 ? nis / static_cast<double>(dimensions)
                          : std::numeric_limits<double>::quiet_NaN();
  }
};

// The smallest contact probability whose stance-foot update counts towards InnovationStats.
constexpr double kNisMinProbability = 0.5;

// Where a filter starts when more is known than a pose (section 57.9: stationary initialisation,
// estimation/engineering/stationary_init.hpp): the base state, the IMU biases, and how well roll
// and pitch are known.
struct InitialState {
  EstimateSample x;
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();  // gyro bias [rad/s]
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();  // accelerometer bias [m/s^2]
  // [rad] standard deviation of roll and pitch (world x and y); NaN: the filter's own prior.
  double sigma_tilt = std::numeric_limits<double>::quiet_NaN();
};

// Throws std::invalid_argument naming the field for non-finite biases or a sigma_tilt that is
// neither NaN nor positive and finite.
inline void checkInitialState(const InitialState& s, const std::string& who) {
  const auto fail = [&](const char* what) {
    throw std::invalid_argument(who + ": InitialState." + what);
  };
  if (!s.b_g.allFinite()) fail("b_g must be finite");
  if (!s.b_a.allFinite()) fail("b_a must be finite");
  if (!std::isnan(s.sigma_tilt) && !(s.sigma_tilt > 0.0 && std::isfinite(s.sigma_tilt)))
    fail("sigma_tilt must be NaN (the filter's prior) or positive and finite");
}

// The contract every estimator keeps (tests/estimation/estimator_contract_test.cpp checks it for
// all of them on the same inputs):
//  - reset(x0) starts over from x0 with the estimator's prior covariance and clears health().
//  - The first sample after reset() is never integrated, whatever its dt: there is no earlier IMU
//    sample to hold over the interval. Its contacts are used.
//  - dt == 0 later on (two samples at one instant): nothing is integrated; contacts are used.
//  - 0 < dt <= InputLimits::max_dt: the previous admitted IMU sample is held over dt.
//  - dt > max_dt: a gap (Fault::kTimeGap). Nothing is integrated across it; the estimator
//    restarts from its current estimate as reset() would (prior covariance, biases and feet
//    forgotten) and takes the sample as a first sample.
//  - An IMU sample beyond the sensor's range (Fault::kGyroRange, kAccelRange) is not admitted:
//    the previous admitted sample stays held over the next interval. A stance foot beyond range
//    (kContactRange) is dropped from that sample.
//  - Feet: any id in [0, 8). An estimator with fewer foot states than feet in stance gives them
//    slots (estimation/foot_slots.hpp) and leaves the extra ones out (kNoFootSlot).
//  - Input no caller can mean (non-finite numbers, dt < 0, a foot id outside [0, 8) or given
//    twice, a covariance that is not symmetric positive definite) throws
//    std::invalid_argument naming the field and the time, before anything changes.
//  - After every step the estimate is finite and physical and, for a filter, P is finite with a
//    positive diagonal; every HealthGuard::kFullCheckInterval steps P is also checked symmetric
//    and positive definite (LDLT), and the state that passes becomes the last good one. If a check
//    fails, the filter recovers (kStateUnhealthy): it returns to the last state that passed the
//    full check, with the prior covariance. estimate() is never NaN.
class Estimator {
 public:
  virtual ~Estimator() = default;
  virtual std::string name() const = 0;
  // Restarts from the state x0 (its time is the time of the first sample that follows).
  virtual void reset(const EstimateSample& x0) = 0;  // implementations clear health_
  // reset(s.x), then, in a filter that carries them, the biases from s and the roll and pitch
  // prior from s.sigma_tilt (yaw keeps the filter's prior). Estimators without bias states keep
  // this default, which uses the pose alone.
  virtual void initialise(const InitialState& s) {
    checkInitialState(s, name());
    reset(s.x);
  }
  // Consumes one IMU sample and the contacts measured with it.
  virtual void step(const StepInput& in) = 0;
  virtual EstimateSample estimate() const = 0;
  // The covariance of estimate(), for filters; none for estimators that do not keep one.
  virtual std::optional<BaseCovariance> covariance() const { return std::nullopt; }
  // Inputs rejected and recoveries since the last reset() (estimation/health.hpp).
  const Health& health() const { return health_; }
  // The stance-foot NIS since the last reset() (InnovationStats; kept across the contract's
  // restarts, a gap or a recovery, as health() is), for the filters that compute it (ESKF, InEKF,
  // linear KF); none for the others.
  virtual std::optional<InnovationStats> stanceInnovations() const { return std::nullopt; }

 protected:
  // The copies admit() makes, only when a foot is dropped or moved to another slot.
  struct InputCopies {
    std::optional<StepInput> admitted, slotted;
  };
  // One sample as the contract admits it: the input step() works on, and whether its IMU reading
  // was admitted (if not, the previous admitted one stays held).
  struct Admitted {
    const StepInput& in;
    bool imu;
  };

  // The input rules of the contract above, the start of every step(): throws on invalid input
  // before anything changes, drops out-of-range feet, checks the IMU sample, and applies the gap
  // rule (restart(), after which the estimator has no previous sample).
  Admitted admit(const StepInput& raw, bool has_previous, const InputLimits& limits,
                 const char* who, InputCopies& copies) {
    checkStepInput(raw, leg_odometry::kMaxContacts, who);
    return admitChecked(admitContacts(raw, limits, health_, copies.admitted), has_previous, limits);
  }
  // The same for a filter with N foot states: stance feet are also given their slots.
  template <int N>
  Admitted admit(const StepInput& raw, bool has_previous, const InputLimits& limits,
                 const char* who, InputCopies& copies, FootSlots<N>& slots) {
    checkStepInput(raw, leg_odometry::kMaxContacts, who);
    const StepInput& in = admitContacts(raw, limits, health_, copies.admitted);
    return admitChecked(slots.map(in, copies.slotted, health_), has_previous, limits);
  }

  // For reset(): a new health record, and x0 as the last good state.
  void startHealth(const EstimateSample& x0) {
    health_ = Health{};
    innovations_ = InnovationStats{};
    guard_.reset(x0);
  }
  // Restarts from x keeping the health record (and the NIS): the gap rule above.
  void restart(const EstimateSample& x) {
    const Health kept = health_;
    const InnovationStats kept_innovations = innovations_;
    reset(x);
    health_ = kept;
    innovations_ = kept_innovations;
  }
  // The recovery rule: back to the last good state, at time t, with the prior covariance.
  void recover(double t) {
    health_.record(Fault::kStateUnhealthy, t);
    EstimateSample x = guard_.lastGood();
    x.t = t;
    restart(x);
  }

  Health health_;
  HealthGuard guard_;
  InnovationStats innovations_;  // the filters that compute it add to it (stanceInnovations())

 private:
  Admitted admitChecked(const StepInput& in, bool has_previous, const InputLimits& limits) {
    const bool imu = admitImu(in, limits, health_);
    if (has_previous && in.dt > limits.max_dt) {
      health_.record(Fault::kTimeGap, in.t);
      restart(estimate());  // nothing integrated across the gap; from here a first sample
    }
    return {in, imu};
  }
};

}  // namespace legkit
