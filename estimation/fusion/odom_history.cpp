#include "estimation/fusion/odom_history.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace legkit::fusion {

OdomHistory::OdomHistory(std::size_t capacity) {
  if (capacity < 2) {
    throw std::invalid_argument("OdomHistory: capacity " + std::to_string(capacity) +
                                ": expected at least 2 samples (interpolation needs two)");
  }
  buffer_.resize(capacity);
}

void OdomHistory::push(const OdomPose& pose) {
  if (!std::isfinite(pose.t)) throw std::invalid_argument("OdomHistory::push: non-finite time");
  if (size_ > 0 && !(pose.t > newestTime())) {
    throw std::invalid_argument("OdomHistory::push: time " + std::to_string(pose.t) +
                                " is not after the newest sample's " +
                                std::to_string(newestTime()));
  }
  if (!pose.R_OB.matrix().allFinite() || !pose.p_OB.allFinite() || !pose.cov.allFinite()) {
    throw std::invalid_argument("OdomHistory::push: non-finite pose or covariance at t = " +
                                std::to_string(pose.t));
  }
  if (size_ < buffer_.size()) {
    buffer_[(head_ + size_) % buffer_.size()] = pose;
    ++size_;
  } else {
    buffer_[head_] = pose;  // overwrite the oldest
    head_ = (head_ + 1) % buffer_.size();
  }
}

double OdomHistory::oldestTime() const {
  if (size_ == 0) throw std::out_of_range("OdomHistory::oldestTime: empty");
  return sample(0).t;
}

double OdomHistory::newestTime() const {
  if (size_ == 0) throw std::out_of_range("OdomHistory::newestTime: empty");
  return sample(size_ - 1).t;
}

OdomHistory::Result OdomHistory::at(double t) const {
  Result r;
  if (!std::isfinite(t)) {
    r.status = Lookup::kNotFinite;
    return r;
  }
  if (size_ == 0) return r;  // kEmpty
  if (t < sample(0).t) {
    r.status = Lookup::kTooOld;
    return r;
  }
  if (t > sample(size_ - 1).t) {
    r.status = Lookup::kInFuture;
    return r;
  }
  // The last sample with time <= t (binary search over the ring's logical order).
  std::size_t lo = 0, hi = size_ - 1;
  while (lo < hi) {
    const std::size_t mid = (lo + hi + 1) / 2;
    if (sample(mid).t <= t) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  r.status = Lookup::kOk;
  const OdomPose& a = sample(lo);
  if (a.t == t || lo + 1 == size_) {
    r.pose = a;
    return r;
  }
  const OdomPose& b = sample(lo + 1);
  const double alpha = (t - a.t) / (b.t - a.t);
  r.pose.t = t;
  r.pose.R_OB = a.R_OB.interpolate(b.R_OB, alpha);  // R_a Exp(alpha Log(R_a^T R_b))
  r.pose.p_OB = a.p_OB + alpha * (b.p_OB - a.p_OB);
  r.pose.cov = a.cov + alpha * (b.cov - a.cov);
  return r;
}

const char* toString(OdomHistory::Lookup status) {
  switch (status) {
    case OdomHistory::Lookup::kOk:
      return "ok";
    case OdomHistory::Lookup::kEmpty:
      return "the odometry history is empty";
    case OdomHistory::Lookup::kTooOld:
      return "older than the odometry history";
    case OdomHistory::Lookup::kInFuture:
      return "after the newest odometry sample";
    case OdomHistory::Lookup::kNotFinite:
      return "non-finite time";
  }
  return "?";
}

}  // namespace legkit::fusion
