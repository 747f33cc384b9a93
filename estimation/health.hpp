// What every estimator guards against, and how it reports it: the health contract of the
// Estimator interface (estimation/estimator.hpp says when each rule applies).
//
// Three kinds of trouble, three answers:
//  - input a caller can never mean (NaN or inf, dt < 0, an unknown foot id, an asymmetric
//    covariance): step() throws std::invalid_argument naming the field and the time, before
//    anything changes;
//  - finite input beyond what a sensor can physically report (a 1e10 m/s^2 spike, a 10 s gap, a
//    foot 1 km from the body, a variance of 1e30 m^2): the sample, or that part of it, is not
//    used, and the reason is counted here;
//  - numerical trouble inside the filter (an innovation covariance that does not factorise, a
//    state that is no longer finite, a covariance that lost symmetry or positive definiteness): the
//    update is skipped, or the filter recovers by the rule below, and that is counted too.
// An estimate is never NaN: a filter that cannot keep one healthy falls back to its last good
// state.
#pragma once

#include <array>
#include <cstdint>

namespace legkit {

// Physical limits of the inputs. The defaults fit a Go2-class robot with a consumer MEMS IMU
// (a 2000 deg/s gyro, a 16 g accelerometer) sampled at 100 Hz or faster.
struct InputLimits {
  double gyro_max = 34.906585039886593;  // [rad/s] per axis: 2000 deg/s
  double accel_max = 156.90640;          // [m/s^2] per axis: 16 g
  double max_dt = 0.1;                   // [s] a longer step is a gap: not integrated
  double foot_distance_max = 5.0;        // [m] |p_body| of a stance foot: longer than any leg
  // [m^2] per axis. A "don't trust this" variance of 1e6 m^2 is fine; beyond 1e8 (10 km) the
  // measurement carries nothing and only costs the filter's arithmetic its digits.
  double foot_variance_max = 1e8;
  double foot_speed_max = 20.0;  // [m/s] |v_body| of a stance foot
  // An estimate beyond these is not a legged robot's state any more: the filter recovers.
  double speed_max = 50.0;    // [m/s]
  double position_max = 1e6;  // [m] from the origin
};

// Why a sample (or part of it) was not used, or why the filter had to recover.
enum class Fault : int {
  kGyroRange,       // |w_m| beyond gyro_max on some axis: the previous IMU sample is held instead
  kAccelRange,      // |a_m| beyond accel_max on some axis: the previous IMU sample is held instead
  kTimeGap,         // dt > max_dt: not integrated; the filter re-initialises its covariance
  kContactRange,    // a stance foot beyond foot_distance_max or a variance beyond its bound: unused
  kUpdateFailed,    // an innovation covariance did not factorise: that update is skipped
  kStateUnhealthy,  // state not finite, or P not symmetric positive definite: recovered
  kNoFootSlot,      // more feet in stance than the filter has foot states: the extra one unused
  // No foot in stance for longer than the contact pipeline's bound (a contact source gone
  // silent: the filter is dead reckoning). Counted once per such stretch, by the pipeline
  // (estimation/contact_pipeline.hpp), never by a filter.
  kNoContact,
  // A measurement whose innovation failed the filter's chi-square gate (GatingParams,
  // estimation/engineering/gating.hpp): that update is skipped. Counted once per gated foot.
  kGated,
  kCount
};

// A short name for each fault, for tables and messages.
constexpr const char* faultName(Fault f) {
  constexpr std::array<const char*, static_cast<int>(Fault::kCount)> names = {
      "gyro out of range",  "accelerometer out of range",
      "time gap",           "contact out of range",
      "update failed",      "state unhealthy (recovered)",
      "no free foot state", "no contact for longer than the bound",
      "innovation gated"};
  return names[static_cast<int>(f)];
}

// The running record an estimator keeps of the faults above. Fixed size: counting never
// allocates.
struct Health {
  std::array<std::uint64_t, static_cast<int>(Fault::kCount)> count{};
  Fault last_fault = Fault::kCount;  // kCount: none yet
  double last_fault_t = 0.0;         // time of the sample that raised it [s]

  void record(Fault f, double t) {
    ++count[static_cast<int>(f)];
    last_fault = f;
    last_fault_t = t;
  }
  std::uint64_t operator[](Fault f) const { return count[static_cast<int>(f)]; }
  std::uint64_t total() const {
    std::uint64_t n = 0;
    for (const std::uint64_t c : count) n += c;
    return n;
  }
  // True while the filter never had to recover (rejected inputs alone do not make it unhealthy).
  bool healthy() const { return (*this)[Fault::kStateUnhealthy] == 0; }
};

}  // namespace legkit
