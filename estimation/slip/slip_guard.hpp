// What a filter does with a foot the slip detector accuses (section 57.7, "after a slip is
// detected"): the reactions of the chapter's table, applied to the filter's input so that every
// estimator gets them without a change of its own.
//   kNone     the input unchanged (the detector still reports)
//   kInflate  R_i <- R_i * alpha_inflate for every slipping foot (SlipParams::inflate): the
//             foot's measurement covariance (ContactMeasurement::cov) grows, a mild slip keeps a
//             weak vote. While all feet slip (the IMU-vs-legs test), every foot is inflated.
//   kDrop     every slipping foot is removed from the input (p_c,i <- 0). A filter with foot
//             states (ESKF, InEKF) then re-initialises the foot from the kinematics when it comes
//             back: a touchdown where the foot stopped sliding.
//   kImuOnly  as kDrop, and while all feet slip (SlipReport::all_slipping) every foot is dropped:
//             the filter runs on the IMU alone until the legs agree with it again.
#pragma once

#include <optional>
#include <string>

#include "estimation/slip/slip_detector.hpp"

namespace legkit::slip {

enum class SlipReaction { kNone, kInflate, kDrop, kImuOnly };

// "none", "inflate", "drop", "imu-only"; nullopt for anything else.
std::optional<SlipReaction> slipReactionByName(const std::string& name);
// The name slipReactionByName takes.
const char* slipReactionName(SlipReaction reaction);

class SlipGuard {
 public:
  // Throws what SlipDetector's constructor throws.
  SlipGuard(const SlipParams& params, SlipReaction reaction);

  // Forgets the detector's anchor (call with the filter's reset()).
  void reset() { detector_.reset(); }

  // Checks `in` against the filter's previous estimate x and covariance P (nullopt: an estimator
  // without one, SlipDetector::check(in, x)), applies the reaction and returns the input the
  // filter should step on: `in` itself when nothing changes, else a copy held in `storage`.
  // The report, when asked for, is the detector's (before the reaction).
  const StepInput& apply(const StepInput& in, const EstimateSample& x,
                         const std::optional<BaseCovariance>& P, std::optional<StepInput>& storage,
                         SlipReport* report = nullptr);

  SlipReaction reaction() const { return reaction_; }
  const SlipDetector& detector() const { return detector_; }

 private:
  SlipDetector detector_;
  SlipReaction reaction_;
};

}  // namespace legkit::slip
