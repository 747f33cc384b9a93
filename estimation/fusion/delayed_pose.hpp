// What the filters' pose updates share (section 57.8, "pose injection"): the outcome of one
// update, the check of a pose before it is used, and the chi-square gate of its 6-dof innovation.
// InvariantEkf::updatePose and Eskf::updatePose (estimation/invariant/) use these; so does
// DelayedFilter (delayed_filter.hpp), which counts the outcomes. The checks are defined in
// delayed_pose.cpp: their LLT, in a header every filter includes, cost each including file 1-2 s
// of compile time.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "estimation/engineering/gating.hpp"
#include "estimation/fusion/pose_measurement.hpp"

namespace legkit::fusion {

// The outcome of one pose update. Only kUsed changes the filter's state.
enum class PoseUpdate {
  kUsed,      // applied
  kNotValid,  // the pose's valid flag is false: not used
  kGated,     // its innovation failed the filter's chi-square gate (Fault::kGated counted)
  kFailed,    // the innovation covariance did not factorise (Fault::kUpdateFailed counted)
};

// The gate of a 6-dof pose innovation: d^2 = nu^T S^-1 nu against the chi-square quantile of
// 6 dof at the probability of the chapter's n-sigma rule (engineering/gating.hpp).
inline double poseGateThreshold(const engineering::GatingParams& gating) {
  return engineering::chiSquareQuantile(6, engineering::nSigmaProbability(gating.n_sigma));
}

// What is wrong with a pose, if anything, and which field (for messages and counts).
struct PoseCheck {
  enum class Problem { kNone, kNotFinite, kNotPositiveDefinite } problem = Problem::kNone;
  const char* what = "";  // e.g. "cov is not symmetric" (the field first)
  explicit operator bool() const { return problem == Problem::kNone; }  // usable
};

// The pose's time, attitude and position finite, its covariance finite, symmetric (to 1e-9 of its
// largest entry) and positive definite (LLT). Nothing allocates.
PoseCheck checkPose(const PoseMeasurement& z);

// Throws std::invalid_argument "<who>::updatePose at t = <z.t>: PoseMeasurement.<field> ..."
// unless checkPose(z) passes.
void checkPoseMeasurement(const PoseMeasurement& z, const char* who);

}  // namespace legkit::fusion
