// From log rows to estimator inputs on detected contacts (sections 57.6 and 57.7): per row,
//   signals (LogFrontend::signals, with the estimator's estimate of the previous step)
//   -> a contact detector (or the log's contact_ flags for the source "truth")
//   -> StepInput (stance feet weighted by their contact probability, LogFrontend::input)
//   -> RollingFoot (option: a stance foot is the ground point its sphere touched, not the
//      sphere's centre, which rolls; joint logs only)
//   -> SlipGuard (57.7: each stance foot's velocity residual against the estimate and its
//      covariance; the reaction chosen: none, inflate R, drop the foot, IMU only while all slip)
//   -> the caller hands it to the estimator.
// The detector judges with the last estimate and the estimator uses the detection in this step
// (57.6's chicken-and-egg rule). The pipeline also watches for silence: no foot in stance for
// longer than no_contact_bound is Fault::kNoContact in its health(), once per such stretch, so
// that a run whose contact source went quiet (a filter reduced to dead reckoning) says so.
// Fixed size: step() never allocates (the detector's update() does not either).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "estimation/contact/contact_detector.hpp"
#include "estimation/contact/detectors.hpp"
#include "estimation/contact/soft_contact.hpp"
#include "estimation/estimator.hpp"
#include "estimation/health.hpp"
#include "estimation/leg_odometry/rolling_foot.hpp"
#include "estimation/log_frontend.hpp"
#include "estimation/slip/slip_guard.hpp"
#include "io/log.hpp"

namespace legkit {

struct PipelineOptions {
  // "truth": the log's contact_ columns (the physics simulator writes the true contact there; a
  // robot's log may carry its own flags); otherwise a detector, one of contact::detectorNames().
  std::string contact = "truth";
  // The stance point on the ground instead of the foot sphere's centre (RollingFoot); used on
  // logs with joints (the sphere's roll comes from the joint rates).
  bool rolling_foot = true;
  double no_contact_bound = 0.5;    // [s] longest stretch without a stance foot before kNoContact
  contact::SoftContactParams soft;  // how p_c weights a foot (detectors only)
  // What the filter does with a foot found slipping; with kNone the slip check still reports.
  slip::SlipReaction slip = slip::SlipReaction::kNone;
  slip::SlipParams slip_params;
};

class ContactPipeline {
 public:
  // Contacts from `detector`, or, when it is null, from the log's contact columns (then
  // options.contact must be "truth" and the layout must have them). Throws
  // std::invalid_argument naming what is missing, for a bound that is not positive, or what
  // SlipGuard throws for the slip parameters.
  ContactPipeline(const io::LogLayout& layout, const model::QuadrupedKinematics& kinematics,
                  const FrontendNoise& noise, const PipelineOptions& options,
                  std::unique_ptr<contact::ContactDetector> detector = nullptr);
  // The detector named by options.contact, from contact::makeDetector(options.contact, context)
  // (whose errors it throws), or the log's flags for "truth".
  ContactPipeline(const io::LogLayout& layout, const model::QuadrupedKinematics& kinematics,
                  const FrontendNoise& noise, const PipelineOptions& options,
                  const contact::DetectorContext& context);

  // "truth" or the detector's name.
  std::string source() const;
  const PipelineOptions& options() const { return options_; }
  const LogFrontend& frontend() const { return frontend_; }

  // Forgets the detector's state and the health record: the next step() is a run's first row.
  void reset();
  // The input of one row for the estimator, given its estimate x and covariance P after the
  // previous row (after reset(): its initial state). The reference stays valid until the next
  // call.
  const StepInput& step(const io::LogRow& row, double dt, const EstimateSample& x,
                        const std::optional<BaseCovariance>& P);
  // The contact answer of the last step (for the log's flags: probability 0 or 1).
  const contact::ContactEstimate& contacts() const { return contacts_; }
  // The slip check of the last step (before the reaction was applied).
  const slip::SlipReport& slipReport() const { return slip_report_; }
  // kNoContact counts since reset().
  const Health& health() const { return health_; }

 private:
  LogFrontend frontend_;
  PipelineOptions options_;
  std::unique_ptr<contact::ContactDetector> detector_;
  leg_odometry::RollingFoot rolling_;
  slip::SlipGuard guard_;
  contact::ContactEstimate contacts_;
  StepInput input_;                   // from the contacts
  std::optional<StepInput> reacted_;  // the guard's copy when its reaction changed input_
  slip::SlipReport slip_report_;
  Health health_;
  std::optional<double> last_stance_t_;  // last row with a stance foot (or the first row)
  bool silent_ = false;                  // the current stretch has been counted
};

}  // namespace legkit
