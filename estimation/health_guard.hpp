// The checks behind the Estimator contract (estimation/estimator.hpp), written once for every
// estimator: what input is refused outright, what is admitted, and the after-step check with the
// last good state it falls back to.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <optional>

#include "estimation/estimate.hpp"
#include "estimation/health.hpp"
#include "estimation/step_input.hpp"

namespace legkit {

// Throws std::invalid_argument "<who>: InputLimits ..." unless every limit is positive (infinity
// allowed: no limit).
void checkLimits(const InputLimits& limits, const char* who);

// Throws std::invalid_argument "<who>::step at t = <t>: <what>" for input no caller can mean:
// a non-finite time, dt or IMU reading, dt < 0, a contact count out of range, a foot id outside
// [0, max_feet) or given twice, a non-finite foot position or velocity, or a foot covariance that
// is not symmetric positive definite. Builds a message only on failure (no allocation otherwise).
void checkStepInput(const StepInput& in, int max_feet, const char* who);

// True when the IMU sample is within the sensor's range; otherwise records kGyroRange or
// kAccelRange at in.t and returns false (the estimator then keeps holding its previous sample).
bool admitImu(const StepInput& in, const InputLimits& limits, Health& health);

// `in` with every stance foot beyond InputLimits dropped (each recorded as kContactRange). When
// all are within range, the usual case, returns `in` itself and copies nothing; otherwise the
// admitted copy lives in `storage`.
const StepInput& admitContacts(const StepInput& in, const InputLimits& limits, Health& health,
                               std::optional<StepInput>& storage);

// Every step, cheaply: P (a covariance, or an information matrix) is finite and has a positive
// diagonal. One vectorised pass: a NaN or inf anywhere makes the sum non-finite.
template <typename Derived>
bool looksPositiveDefinite(const Eigen::MatrixBase<Derived>& P) {
  return P.diagonal().minCoeff() > 0.0 && std::isfinite(P.sum());
}

// At the full-check interval: P is symmetric to rounding (1e-9 of its largest diagonal entry;
// every filter symmetrises P as it updates it, so asymmetry can only creep in slowly, and the soak
// run measures it below 1e-17) and its LDLT factorisation succeeds with a positive D.
template <typename Derived>
bool isPositiveDefinite(const Eigen::MatrixBase<Derived>& P) {
  const double tolerance = 1e-9 * P.diagonal().cwiseAbs().maxCoeff();
  if (!((P - P.transpose()).array().abs() <= tolerance).all()) return false;
  using Matrix = typename Derived::PlainObject;
  const Eigen::LDLT<Matrix> ldlt(P.derived());
  return ldlt.info() == Eigen::Success && (ldlt.vectorD().array() > 0.0).all();
}

// The estimate is finite, its quaternion a unit one, and its speed and position physical.
bool isSane(const EstimateSample& x, const InputLimits& limits);

// The after-step check of the contract. check() runs the cheap checks every step and the full
// one (symmetry, LDLT) every kFullCheckInterval steps; a state that passes the full check becomes
// the last good one, which the estimator restarts from when a check fails.
class HealthGuard {
 public:
  static constexpr int kFullCheckInterval = 200;  // steps (0.2 s at 1 kHz)

  void reset(const EstimateSample& x0) {
    last_good_ = x0;
    steps_since_full_check_ = 0;
  }
  template <typename Derived>
  bool check(const EstimateSample& x, const Eigen::MatrixBase<Derived>& P,
             const InputLimits& limits) {
    if (!isSane(x, limits) || !looksPositiveDefinite(P)) return false;
    if (++steps_since_full_check_ < kFullCheckInterval) return true;
    steps_since_full_check_ = 0;
    if (!isPositiveDefinite(P)) return false;
    last_good_ = x;
    return true;
  }
  // For estimators without a covariance.
  bool check(const EstimateSample& x, const InputLimits& limits);
  const EstimateSample& lastGood() const { return last_good_; }

 private:
  EstimateSample last_good_;
  int steps_since_full_check_ = 0;
};

}  // namespace legkit
