// The odometry's recent poses by time (section 57.8, loose coupling): a pose measured at t arrives
// ~80 ms later, and T_MO must be measured against the odometry pose AT t, never the newest one
// (at 1 m/s the difference is 8 cm). The proprioceptive filter pushes its pose (and covariance)
// at every sample; the alignment looks up the stamp.
//
// A fixed-capacity ring buffer: the storage is allocated once by the constructor, push() never
// allocates, the oldest sample is overwritten when full (capacity 1024 at 1 kHz keeps ~1 s).
// at(t) interpolates between the two samples around t: the attitude by slerp on SO(3),
// R = R_i Exp(a Log(R_i^T R_i+1)), the position and the covariance linearly (a = (t - t_i) /
// (t_i+1 - t_i); the covariance changes little between two filter samples). It never extrapolates:
// a t before the oldest or after the newest sample is refused with the reason.
// The covariance is the filter's, in the kit's convention (odom frame O):
//   R_OB = Exp(dtheta) R_OB_hat, p_OB = p_OB_hat + dp, (dtheta, dp) ~ N(0, cov).
#pragma once

#include <cstddef>
#include <vector>

#include "estimation/fusion/pose_measurement.hpp"

namespace legkit::fusion {

// One odometry pose: the base in the odom frame O at time t.
struct OdomPose {
  double t = 0.0;                                  // [s]
  lie::SO3d R_OB;                                  // base attitude in odom
  Eigen::Vector3d p_OB = Eigen::Vector3d::Zero();  // base position in odom [m]
  Matrix6d cov = Matrix6d::Zero();                 // of (dtheta, dp), odom frame
};

class OdomHistory {
 public:
  enum class Lookup {
    kOk,
    kEmpty,      // nothing pushed yet
    kTooOld,     // t is before the oldest sample kept (the buffer is too short for the latency)
    kInFuture,   // t is after the newest sample (the odometry has not got there yet)
    kNotFinite,  // t is NaN or infinite
  };
  struct Result {
    Lookup status = Lookup::kEmpty;
    OdomPose pose;  // meaningful only when status == kOk
  };

  // Throws std::invalid_argument for capacity < 2.
  explicit OdomHistory(std::size_t capacity = 1024);

  // Appends a sample. Throws std::invalid_argument (and keeps the history as it was) if its time
  // is not finite or not after the newest sample's, or its pose is not finite.
  void push(const OdomPose& pose);
  // The pose at t, interpolated (see above), or why there is none.
  Result at(double t) const;

  std::size_t size() const { return size_; }
  std::size_t capacity() const { return buffer_.size(); }
  bool empty() const { return size_ == 0; }
  double oldestTime() const;  // throws std::out_of_range when empty
  double newestTime() const;  // throws std::out_of_range when empty
  void clear() { size_ = 0; }

 private:
  const OdomPose& sample(std::size_t k) const {  // k = 0: the oldest
    return buffer_[(head_ + k) % buffer_.size()];
  }
  std::vector<OdomPose> buffer_;
  std::size_t head_ = 0;  // index of the oldest sample
  std::size_t size_ = 0;
};

const char* toString(OdomHistory::Lookup status);

}  // namespace legkit::fusion
