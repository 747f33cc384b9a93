// Delayed pose measurements in a filter (section 57.8): Pronto's scheme of a history and
// re-propagation.
//
// An exteroceptive pose describes the instant z.t but reaches the estimator at z.t_arrival, some
// 80 ms later, when the filter has already integrated 80 IMU samples past z.t. Applying it to the
// current state would compare the pose at z.t with the state at z.t_arrival: a position error of
// the speed times the latency (4 cm at 0.5 m/s). Instead the filter keeps, for every IMU sample k,
// a snapshot of itself after that sample (state, covariance, feet, health: the filter object is a
// value) and the sample's input. A pose is applied to the newest snapshot at or before z.t, and
// the stored inputs after it are run again to the present. The result is exactly the filter that
// would have applied the pose on time, right after sample k (tests/fusion/delayed_filter_test.cpp:
// to 1e-9, in fact bitwise). A pose stamped between two samples is applied at the earlier one,
// up to one IMU period (1 ms) early.
//
// Capacity: a fixed number of samples (kDefaultCapacity = 0.5 s at 1 kHz), allocated at
// construction; step() copies the filter into the ring buffer and allocates nothing.
//
// Rejections, each counted by reason (Stats) and none of them changing anything:
//  - kNotFinite, kNotPositiveDefinite: a non-finite stamp, pose or covariance, or a covariance
//    that is not symmetric positive definite (fusion::checkPose);
//  - kNotValid: the source flags the pose as not to be used;
//  - kTooOld: z.t before the oldest sample held (or no sample yet): it cannot be placed;
//  - kFuture: z.t after the newest sample: the state at that time does not exist yet;
//  - kOutOfOrder: z.t before the stamp of a pose already used. Re-propagation re-runs the stored
//    inputs, not the poses, so placing it would erase the newer pose's correction;
//  - kGated: the filter's chi-square gate (when its gating is on) rejected the innovation;
//  - kFailed: the innovation covariance did not factorise.
//
// One template for InvariantEkf and Eskf (estimation/invariant/) rather than an interface: the
// history stores the filter by value, which needs its concrete type (an interface would need a
// clone() onto the heap, once per sample), and both filters already share the calls it uses
// (reset, initialise, step, estimate, updatePose). delayed_filter.cpp instantiates it for the
// two.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "estimation/estimator.hpp"
#include "estimation/fusion/delayed_pose.hpp"
#include "estimation/fusion/pose_measurement.hpp"

namespace legkit::fusion {

// Why DelayedFilter::updatePose did not use a pose (file comment).
enum class PoseRejection : int {
  kNotFinite,
  kNotPositiveDefinite,
  kNotValid,
  kTooOld,
  kFuture,
  kOutOfOrder,
  kGated,
  kFailed,
  kCount
};

// A short name for each reason, for tables and messages.
const char* poseRejectionName(PoseRejection r);

template <class Filter>
class DelayedFilter {
 public:
  static constexpr int kDefaultCapacity = 500;  // samples: 0.5 s at 1 kHz

  struct Stats {
    std::uint64_t used = 0;
    std::array<std::uint64_t, static_cast<int>(PoseRejection::kCount)> rejected{};
    int last_replayed = 0;  // samples re-run by the last pose used
    std::uint64_t rejections() const {
      std::uint64_t n = 0;
      for (const std::uint64_t c : rejected) n += c;
      return n;
    }
    std::uint64_t operator[](PoseRejection r) const { return rejected[static_cast<int>(r)]; }
  };
  // The outcome of updatePose: used, or the reason it was not.
  struct Result {
    bool used = false;
    PoseRejection reason = PoseRejection::kCount;  // kCount when used
  };

  // Takes the filter as it is (reset or initialised by the caller) with an empty history of
  // `capacity` samples. Throws std::invalid_argument for capacity < 1.
  explicit DelayedFilter(const Filter& filter, int capacity = kDefaultCapacity);

  // The filter's reset / initialise; the history and the pose counts are cleared.
  void reset(const EstimateSample& x0);
  void initialise(const InitialState& s);
  // One IMU sample: the filter's step, then its snapshot and the input into the history (the
  // oldest sample dropped when full). Throws std::invalid_argument, before anything changes, for
  // what the filter's step() refuses and for a time earlier than the previous sample's.
  void step(const StepInput& in);
  // Applies z at its stamp and re-propagates to the newest sample (file comment); a rejected pose
  // is counted and changes nothing. Never throws for a bad pose: it is rejected.
  Result updatePose(const PoseMeasurement& z);

  const Filter& filter() const { return filter_; }
  EstimateSample estimate() const { return filter_.estimate(); }
  const Stats& stats() const { return stats_; }
  int capacity() const { return static_cast<int>(history_.size()); }
  int size() const { return count_; }
  // Stamps of the oldest and the newest sample held (size() > 0).
  double oldestTime() const { return at(0).in.t; }
  double newestTime() const { return at(count_ - 1).in.t; }

 private:
  struct Entry {
    Filter filter;  // after this sample's step
    StepInput in;
  };
  // The i-th sample held, 0 the oldest.
  Entry& at(int i) { return history_[(first_ + i) % history_.size()]; }
  const Entry& at(int i) const { return history_[(first_ + i) % history_.size()]; }
  Result reject(PoseRejection r);
  void clear();

  Filter filter_;
  std::vector<Entry> history_;  // the ring buffer, sized at construction
  int first_ = 0;               // index in history_ of the oldest sample
  int count_ = 0;
  double last_used_t_;  // stamp of the newest pose used (-inf: none)
  Stats stats_;
};

}  // namespace legkit::fusion
