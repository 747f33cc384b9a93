#include "estimation/fusion/delayed_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"

namespace legkit::fusion {

namespace {
constexpr double kNone = -std::numeric_limits<double>::infinity();
}  // namespace

const char* poseRejectionName(PoseRejection r) {
  constexpr std::array<const char*, static_cast<int>(PoseRejection::kCount)> names = {
      "not finite",
      "covariance not SPD",
      "flagged not valid",
      "older than the history",
      "in the future",
      "out of time order",
      "gated",
      "update failed"};
  return names[static_cast<int>(r)];
}

template <class Filter>
DelayedFilter<Filter>::DelayedFilter(const Filter& filter, int capacity)
    : filter_(filter), last_used_t_(kNone) {
  if (capacity < 1) {
    throw std::invalid_argument("DelayedFilter: capacity must be at least 1 sample, got " +
                                std::to_string(capacity));
  }
  history_.assign(static_cast<std::size_t>(capacity), Entry{filter, StepInput{}});
}

template <class Filter>
void DelayedFilter<Filter>::clear() {
  first_ = 0;
  count_ = 0;
  last_used_t_ = kNone;
  stats_ = Stats{};
}

template <class Filter>
void DelayedFilter<Filter>::reset(const EstimateSample& x0) {
  filter_.reset(x0);
  clear();
}

template <class Filter>
void DelayedFilter<Filter>::initialise(const InitialState& s) {
  filter_.initialise(s);
  clear();
}

template <class Filter>
void DelayedFilter<Filter>::step(const StepInput& in) {
  if (count_ > 0 && in.t < newestTime()) {
    std::ostringstream os;
    os << "DelayedFilter::step at t = " << in.t
       << ": time t is earlier than the previous sample's (" << newestTime() << ")";
    throw std::invalid_argument(os.str());
  }
  filter_.step(in);  // throws before anything changes
  const int capacity = this->capacity();
  if (count_ == capacity) {
    first_ = (first_ + 1) % capacity;  // the oldest sample leaves
  } else {
    ++count_;
  }
  Entry& e = at(count_ - 1);
  e.filter = filter_;
  e.in = in;
}

template <class Filter>
typename DelayedFilter<Filter>::Result DelayedFilter<Filter>::reject(PoseRejection r) {
  ++stats_.rejected[static_cast<int>(r)];
  return {false, r};
}

template <class Filter>
typename DelayedFilter<Filter>::Result DelayedFilter<Filter>::updatePose(const PoseMeasurement& z) {
  const PoseCheck check = checkPose(z);
  if (check.problem == PoseCheck::Problem::kNotFinite) return reject(PoseRejection::kNotFinite);
  if (!check) return reject(PoseRejection::kNotPositiveDefinite);
  if (!z.valid) return reject(PoseRejection::kNotValid);
  if (count_ == 0 || z.t < oldestTime()) return reject(PoseRejection::kTooOld);
  if (z.t > newestTime()) return reject(PoseRejection::kFuture);
  if (z.t < last_used_t_) return reject(PoseRejection::kOutOfOrder);

  // k: the newest sample at or before z.t (stamps are non-decreasing: binary search).
  int lo = 0, hi = count_ - 1;  // at(lo).in.t <= z.t holds
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (at(mid).in.t <= z.t) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  const int k = lo;

  // The update on a copy: a gated or failed pose leaves the history and the filter untouched.
  Filter f = at(k).filter;
  switch (f.updatePose(z)) {
    case PoseUpdate::kUsed:
      break;
    case PoseUpdate::kGated:
      return reject(PoseRejection::kGated);
    case PoseUpdate::kFailed:
      return reject(PoseRejection::kFailed);
    case PoseUpdate::kNotValid:  // checked above
      return reject(PoseRejection::kNotValid);
  }
  // Re-propagation: the stored inputs after k, each snapshot rewritten (a later pose starts
  // from the corrected history).
  at(k).filter = f;
  for (int i = k + 1; i < count_; ++i) {
    Entry& e = at(i);
    f.step(e.in);
    e.filter = f;
  }
  filter_ = f;
  last_used_t_ = z.t;
  ++stats_.used;
  stats_.last_replayed = count_ - 1 - k;
  return {true, PoseRejection::kCount};
}

template class DelayedFilter<invariant::InvariantEkf>;
template class DelayedFilter<invariant::Eskf>;

}  // namespace legkit::fusion
