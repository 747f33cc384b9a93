// Innovation gating (section 57.9): a measurement whose innovation is too unlikely under the
// filter's own innovation covariance is not used. The test is the Mahalanobis distance
// d^2 = r^T S^-1 r against the chi-square quantile of the innovation's dimension at the
// probability of the chapter's n-sigma rule (erf(n / sqrt 2): 3 sigma -> 0.9973).
//
// What each filter gates (the filters' headers say how): every stance-foot measurement that is an
// update (not a touchdown, which only places the foot), 3 dof, with its sequential innovation
// covariance S; in the linear KF also the leg-odometry velocity, 3 dof, each block against its
// own marginal S_bb of the stacked update; in the TSIF, which has no innovation, the kinematics
// residual at the IMU prediction of x_{k+1} against J Lambda_pred^-1 J^T + Cov (tsif.hpp).
// A gated measurement is left out of that step and counted once as Fault::kGated.
//
// Lock-out. A foot whose state has drifted (a slip the filter did not model) fails the gate at
// every step: gated forever, its state never corrects itself. So a foot gated without a break for
// longer than max_gated_time is re-initialised from its measurement as at a touchdown: the foot
// state moves, the base does not (a touchdown measurement places the foot and corrects nothing
// else). A base state that drifted shows as every foot gated at once; re-anchoring the feet then
// keeps the legs' information flowing instead of dead reckoning on the IMU.
#pragma once

#include <array>
#include <limits>

namespace legkit::engineering {

struct GatingParams {
  bool enabled = false;  // off in the library's defaults; the settings file turns it on
  double n_sigma = 3.0;  // the chapter's rule: reject beyond n sigma (as a probability, per dof)
  // [s] a foot gated at every step for this long is re-initialised from its measurement (the
  // lock-out rule above; 0: at once); a trot's stance (~0.2 s) usually ends first.
  double max_gated_time = 0.2;
};

// Throws std::invalid_argument naming the field for n_sigma <= 0 or max_gated_time < 0 (or
// non-finite values).
void checkGatingParams(const GatingParams& params, const char* who);

// P(|x| < n sigma) for a scalar Gaussian: erf(n / sqrt 2).
double nSigmaProbability(double n_sigma);
// The chi-square CDF of `dof` degrees of freedom (1 <= dof <= 64), in closed form: the regularised
// lower incomplete gamma P(k/2, x/2) by the recurrence P(a + 1, y) = P(a, y) - y^a e^-y /
// Gamma(a+1) from P(1/2, y) = erf(sqrt y) or P(1, y) = 1 - e^-y. Exact to rounding for the small
// dof a filter gates (the tests compare it with table values).
double chiSquareCdf(int dof, double x);
// The x with chiSquareCdf(dof, x) = p, by bisection to 1e-12 relative (p in (0, 1); p = 1 gives
// infinity, for an n_sigma so large nothing is gated).
double chiSquareQuantile(int dof, double p);

// The gate of one filter: its threshold for a 3-dof innovation, and per foot the time since it
// was first gated without a break. Fixed size; nothing allocates.
class FootGate {
 public:
  static constexpr int kMaxFeet = 8;
  enum class Decision { kUse, kGate, kReinitialise };

  // Throws as checkGatingParams does, naming `who`.
  explicit FootGate(const GatingParams& params = {}, const char* who = "FootGate");
  bool enabled() const { return params_.enabled; }
  double threshold() const { return threshold_; }  // chi2_3 quantile at p(n_sigma)
  // Decides foot `foot`'s measurement at time t with Mahalanobis distance d2 (3 dof): kUse when
  // it passes (and its clock stops), kGate when it fails, kReinitialise when it has failed at
  // every step for at least max_gated_time (its clock stops: it starts afresh).
  Decision decide(int foot, double d2, double t);
  // The foot left stance (or was placed anew): its clock stops.
  void clear(int foot) { gated_since_[foot] = kNever; }
  void reset() { gated_since_.fill(kNever); }

 private:
  static constexpr double kNever = std::numeric_limits<double>::quiet_NaN();
  GatingParams params_;
  double threshold_;
  std::array<double, kMaxFeet> gated_since_{};
};

}  // namespace legkit::engineering
