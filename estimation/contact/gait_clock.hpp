// Method 1 of section 57.6: contact from the gait clock. A foot is "in contact" while the planned
// schedule says stance (gait_schedule.hpp). Zero delay and no sensor, but it answers what the
// planner wanted, not what happened: on uneven ground a foot lands 20-50 ms early or late and
// the clock is wrong for that long.
//
// This file also holds the input check every detector of legkit_contact shares.
#pragma once

#include <string>

#include "estimation/contact/contact_detector.hpp"
#include "estimation/contact/gait_schedule.hpp"

namespace legkit::contact {

// The contract of ContactDetector::update: throws std::invalid_argument, naming `detector`, the
// field and the sample time, when num_feet is outside [1, kMaxFeet] or dt is negative or not
// finite. Everything else is a per-foot problem, not an exception.
void checkSignals(const ContactSignals& signals, const char* detector);

class GaitClockDetector : public ContactDetector {
 public:
  // Throws std::invalid_argument for a schedule no robot can walk: period not positive, duty
  // not positive, num_feet outside [1, kMaxFeet], a non-finite offset or start.
  explicit GaitClockDetector(const GaitSchedule& gait);

  std::string name() const override { return "gait-clock"; }
  void reset() override {}
  // contact = plannedStance(gait, foot, t), probability 0 or 1, force NaN; never a problem for
  // a foot of the schedule. A foot beyond the schedule's num_feet has the problem "foot not in
  // the gait schedule" (the clock says nothing about it).
  ContactEstimate update(const ContactSignals& signals) override;

  const GaitSchedule& gait() const { return gait_; }

 private:
  GaitSchedule gait_;
};

}  // namespace legkit::contact
