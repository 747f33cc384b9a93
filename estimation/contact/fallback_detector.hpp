// A chain of detectors in a stated order (section 57.6, bad input): per foot and sample the answer
// of the first detector that could decide. A foot sensor that reads NaN, saturates for too long or
// goes negative hands that foot to the next detector (say the force estimated from the joint
// torques, then the kinematic detector, then the gait clock) instead of reporting "no contact";
// every hand-over is counted, and the first and the last are kept with the foot, the time, the
// detector that failed and its reason.
//
// Lazy: the chain costs only what it uses. At each sample detector k runs only when some foot
// needs it, i.e. every detector before k had a problem for that foot; while every foot is healthy
// only the first detector runs, so the chain costs what that detector costs. A detector that was
// not run at the previous sample is reset() before it runs again: it starts clean rather than
// from timers and integrals that stopped at its last run. Its first samples are then a cold
// start: a Schmitt trigger on the torques starts at "no contact" and needs T_on to switch on; the
// kinematic detector re-anchors its ground height to the lowest foot; a momentum observer
// answers "momentum observer converging" for its settle_time (60 ms by default), and for those
// samples the foot goes on to the next detector (the kinematic one in the recommended chain).
// Measured (`bench_pipeline --benchmark_filter=eskf`, CPU per ESKF step on the physics trot, load
// ~2.5): the recommended chain 5.67 us against 5.64 us for the sensor Schmitt alone; 14.7 us when
// every detector ran on every sample.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "estimation/contact/contact_detector.hpp"

namespace legkit::contact {

constexpr int kMaxChain = 8;  // the longest chain a FallbackDetector takes

// One hand-over: detector `detector` (index in the chain) had `problem` for `foot` at time t, so
// the foot went to a later detector (or to none: then the foot's answer carries the problem).
struct FallbackReport {
  int foot = -1;
  double t = 0.0;
  int detector = -1;
  const char* problem = nullptr;  // nullptr: no hand-over yet
};

struct FallbackReports {
  // failed[foot][k]: samples on which detector k had a problem for the foot (and the chain went
  // on); answered[foot][k]: samples on which detector k gave the foot's answer.
  std::array<std::array<long, kMaxChain>, kMaxFeet> failed{}, answered{};
  // Samples on which no detector of the chain could decide for the foot.
  std::array<long, kMaxFeet> undecided{};
  // ran[k]: samples on which detector k ran (update() called); restarts[k]: how many of those
  // began with a reset() because it had not run at the sample before.
  std::array<long, kMaxChain> ran{}, restarts{};
  FallbackReport first, last;
};

class FallbackDetector : public ContactDetector {
 public:
  // Throws std::invalid_argument for an empty chain, a null detector or more than kMaxChain.
  explicit FallbackDetector(std::vector<std::unique_ptr<ContactDetector>> order);

  // The chain's names joined by '>', e.g. "schmitt>kinematic>gait-clock".
  std::string name() const override { return name_; }
  // Resets every detector of the chain and the reports.
  void reset() override;
  // Per foot the first usable answer in the chain's order; when none is usable, the last
  // detector's answer (its problem set: never a silent "no contact"). Runs detector k only for
  // the feet that reach it (see above).
  ContactEstimate update(const ContactSignals& signals) override;

  const FallbackReports& reports() const { return reports_; }
  // Which detector of the chain answered each foot at the last update (-1: none could).
  const std::array<int, kMaxFeet>& source() const { return source_; }
  // The problem detector k had with `foot` at the last update, nullptr when it answered the foot
  // or was not asked (a detector before it answered).
  const char* problem(int foot, int k) const { return problems_[foot][k]; }
  int size() const { return static_cast<int>(order_.size()); }
  const ContactDetector& detector(int k) const { return *order_.at(k); }

 private:
  std::vector<std::unique_ptr<ContactDetector>> order_;
  std::string name_;
  FallbackReports reports_;
  std::array<int, kMaxFeet> source_{};
  std::array<std::array<const char*, kMaxChain>, kMaxFeet> problems_{};  // of the last update
  // Whether detector k ran at the previous sample (true after construction and reset(): a fresh
  // detector needs no reset).
  std::array<bool, kMaxChain> ran_prev_{};
};

}  // namespace legkit::contact
