// How well a contact detector agrees with the true contact (section 57.6), from two per-sample
// flag sequences of the same log: what a detector said and what the physics knew.
//
//  - precision, recall, F1: sample-wise, a sample of one foot being positive when in contact;
//    true/false positives and false negatives summed over the feet, then
//      precision = TP / (TP + FP), recall = TP / (TP + FN), F1 = 2 TP / (2 TP + FP + FN)
//    (NaN when the denominator is 0: no detected contact, no true contact, neither);
//  - events: a touchdown is a rise of the flag between samples k-1 and k (at t_k), a lift-off a
//    fall; toggles in the first kEventWindow of the log are none (a detector starting up). Each
//    true touchdown, in time order, is matched to the nearest detected rise of the same foot within
//    +-kEventWindow that no earlier touchdown took; its delay is t_detected - t_true (positive: the
//    detector is late). Lift-offs the same with falls. A true event without a match is missed; it
//    has no delay;
//  - delays: mean and 95th percentile (nearest rank: the ceil(0.95 n)-th smallest) of the
//    matched delays over all feet, in ms (NaN when none matched);
//  - chatter: detected rises and falls that match no true event (spurious toggles), summed over
//    the feet, per minute of log (t_last - t_first).
#pragma once

#include <array>
#include <vector>

namespace legkit::eval {

constexpr int kScoredFeet = 8;        // the kit's most feet (leg_odometry::kMaxContacts)
constexpr double kEventWindow = 0.1;  // a detected toggle matches a true event within +-100 ms
using FootFlags = std::array<bool, kScoredFeet>;  // one sample: per foot, contact or not

struct ContactScores {
  double precision = 0.0, recall = 0.0, f1 = 0.0;
  double touchdown_delay_mean = 0.0, touchdown_delay_p95 = 0.0;  // [ms]
  double liftoff_delay_mean = 0.0, liftoff_delay_p95 = 0.0;      // [ms]
  double chatter_per_min = 0.0;                    // spurious detected toggles per minute, all feet
  int touchdowns = 0, liftoffs = 0;                // true events, all feet
  int missed_touchdowns = 0, missed_liftoffs = 0;  // true events with no detected match
  int spurious_toggles = 0;                        // detected toggles with no true match
};

// Scores `detected` against `truth` (one entry per sample, sample k at time t[k]) over feet
// 0..num_feet-1. Throws std::invalid_argument when the three lengths differ, there are fewer than
// two samples, num_feet is outside [1, kScoredFeet] or t does not increase strictly.
ContactScores scoreContacts(const std::vector<double>& t, const std::vector<FootFlags>& detected,
                            const std::vector<FootFlags>& truth, int num_feet);

}  // namespace legkit::eval
