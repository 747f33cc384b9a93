// A chain of detectors in a stated order (section 57.6, bad input): per foot and sample the answer
// of the first detector that could decide. A foot sensor that reads NaN, saturates for too long or
// goes negative hands that foot to the next detector (say the force estimated from the joint
// torques, then the kinematic detector, then the gait clock) instead of reporting "no contact";
// every hand-over is counted, and the first and the last are kept with the foot, the time, the
// detector that failed and its reason. Every detector of the chain runs on every sample (their
// timers and integrals stay current), so a foot can move to a later detector and back.
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
  // detector's answer (its problem set: never a silent "no contact").
  ContactEstimate update(const ContactSignals& signals) override;

  const FallbackReports& reports() const { return reports_; }
  // Which detector of the chain answered each foot at the last update (-1: none could).
  const std::array<int, kMaxFeet>& source() const { return source_; }
  int size() const { return static_cast<int>(order_.size()); }
  const ContactDetector& detector(int k) const { return *order_.at(k); }

 private:
  std::vector<std::unique_ptr<ContactDetector>> order_;
  std::string name_;
  FallbackReports reports_;
  std::array<int, kMaxFeet> source_{};
};

}  // namespace legkit::contact
