// From log rows to estimator inputs on detected contacts (sections 57.6 and 57.7): per row,
//   signals (LogFrontend::signals, with the estimator's estimate of the previous step)
//   -> a contact detector (or the log's contact_ flags for the source "truth")
//   -> StepInput (stance feet weighted by their contact probability, LogFrontend::input, in the
//      IMU frame; foot columns without velocity columns differentiated, FootVelocityDifferentiator)
//   -> RollingFoot (option: a stance foot is the ground point its sphere touched, not the
//      sphere's centre, which rolls; joint logs only)
//   -> SlipGuard (57.7: each stance foot's velocity residual against the estimate and its
//      covariance; the reaction chosen: none, inflate R, drop the foot, IMU only while all slip),
//      on every foot the source put down
//   -> touchdown settling (a foot just put down reaches the filter at p_c = 0 for settle_time,
//      settleWeight: a swing foot to the filters that weigh feet by p_c; the slip check above
//      has seen it whole)
//   -> the caller hands it to the estimator.
// The detector judges with the last estimate and the estimator uses the detection in this step
// (57.6's chicken-and-egg rule). The pipeline also watches for silence: no foot in stance for
// longer than no_contact_bound is Fault::kNoContact in its health(), once per such stretch, so
// that a run whose contact source went quiet (a filter reduced to dead reckoning) says so. And it
// keeps per-foot diagnostics (diagnostics(), contact_diagnostics.hpp): which detector decided
// each foot how often, its hand-overs and their problems, stance, touchdowns, settling, slips.
// Fixed size: step() never allocates (the detector's update() does not either).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "estimation/contact/contact_detector.hpp"
#include "estimation/contact/detectors.hpp"
#include "estimation/contact/fallback_detector.hpp"
#include "estimation/contact/soft_contact.hpp"
#include "estimation/contact_diagnostics.hpp"
#include "estimation/estimator.hpp"
#include "estimation/health.hpp"
#include "estimation/leg_odometry/rolling_foot.hpp"
#include "estimation/log_frontend.hpp"
#include "estimation/slip/slip_guard.hpp"
#include "io/log.hpp"

namespace legkit {

// The kit's touchdown settling time [s] (PipelineOptions::settle_time), which `legkit run` uses
// on physics scenarios and recorded logs. On the physics trot the foot sphere's centre still
// moves about 7.5 mm along the ground and 7.4 mm down in its first 20 ms of contact (the log's
// gt_vf_ foot velocities integrated over 20 ms after each rising gt_contact_, 470 touchdowns of
// the 60 s trot, seed 1), so a leg measurement taken then pins the filter to a point that is
// still moving. A settling foot is handed over at p_c = 0, not removed: the filters that weigh
// feet by p_c (ESKF, InEKF, TSIF, linear KF) let it wander as a swing foot, exactly as if it
// were left out (the same figures to the last digit); leg odometry, which takes a foot whole, is
// not settled. Why the split: removing the foot tripled leg odometry where a real robot's feet
// land softly (a Go1 trot measured outside the kit: 1.55 m with 80 ms against 0.45 m without,
// flags from its log), and on the kit's own physics it did the same on the slower gaits (truth
// contacts, `legkit run --scenario S --contact truth --settle 0|0.08`: physics-turn 0.025 ->
// 0.187 m, physics-walk 0.065 -> 0.227 m; better only on the trots, physics-trot 0.444 -> 0.319,
// physics-real 0.409 -> 0.098). The p_c-weighted filters gain on every physics scenario (the
// fallback chain, stance density 0.01, settle 0 -> 0.08: ESKF physics-trot 0.594 -> 0.231 m,
// physics-real 0.120 -> 0.084, physics-walk 0.195 -> 0.064, physics-turn 0.238 -> 0.078; ANEES
// 12.1 -> 1.5, 2.9 -> 1.8, 5.2 -> 0.6, 8.5 -> 1.0) and on the iCub log (0.028 -> 0.026 m).
// 80 ms: on the trot (truth contacts, stance density 1e-3), 0.05 / 0.08 / 0.12 s gave ESKF 0.24 /
// 0.19 / 0.22 m. Settling acts on the
// filter's input only: the slip check still sees a foot from its touchdown, so a slide at
// touchdown is found as without settling (exercise 57.X, seed 5790: the first slide on the ice,
// 3.754 s, found at 3.756 s with and without it). The library's default stays off because
// settling also changes what that exercise teaches: with it the invariant EKF's velocity RMS
// error on the ice is 0.022 m/s with no slip reaction as with dropping the foot (0.050 and 0.027
// m/s without settling), and the naive controller on the estimate falls at 7.58 s instead of
// 5.05 s (truth: 9.22 s); test_ex57_X.
constexpr double kRecommendedSettleTime = 0.08;

struct PipelineOptions {
  // "truth": the log's contact_ columns (the physics simulator writes the true contact there; a
  // robot's log may carry its own flags); otherwise a detector, one of contact::detectorNames().
  std::string contact = "truth";
  // The stance point on the ground instead of the foot sphere's centre (RollingFoot); used on
  // logs with joints (the sphere's roll comes from the joint rates).
  bool rolling_foot = true;
  // The IMU samples the estimators admit (Estimator's contract): the rolling foot integrates the
  // last admitted gyro sample, as they do.
  InputLimits limits;
  double no_contact_bound = 0.5;    // [s] longest stretch without a stance foot before kNoContact
  contact::SoftContactParams soft;  // how p_c weights a foot (detectors only)
  // What the filter does with a foot found slipping; with kNone the slip check still reports.
  slip::SlipReaction slip = slip::SlipReaction::kNone;
  slip::SlipParams slip_params;
  // Touchdown settling [s] (0: off): a foot the contact source has just put down reaches the
  // filter at p_c = 0 for this long (settleWeight), the slip check whole;
  // kRecommendedSettleTime says why and how long, and why it is off unless asked for.
  double settle_time = 0.0;
};

// The factor on a foot's p_c `since_touchdown` seconds after the contact source put it down:
// 0 before the settling time (p_c held at 0), 1 from then on and always when the settling time
// is 0 (touchdown settling off).
double settleWeight(double since_touchdown, double settle_time);

class ContactPipeline {
 public:
  // Contacts from `detector`, or, when it is null, from the log's contact columns (then
  // options.contact must be "truth" and the layout must have them). Throws
  // std::invalid_argument naming what is missing, for a bound that is not positive, a negative
  // settling time, or what SlipGuard throws for the slip parameters.
  ContactPipeline(const io::LogLayout& layout, const model::QuadrupedKinematics& kinematics,
                  const FrontendNoise& noise, const PipelineOptions& options,
                  std::unique_ptr<contact::ContactDetector> detector = nullptr);
  // The detector named by options.contact, from contact::makeDetector(options.contact, context)
  // (whose errors it throws), or the log's flags for "truth".
  ContactPipeline(const io::LogLayout& layout, const model::QuadrupedKinematics& kinematics,
                  const FrontendNoise& noise, const PipelineOptions& options,
                  const contact::DetectorContext& context);
  // The same two on a front end made by the caller: with an IMU extrinsic, or with a robot's
  // LegKinematics for generic joints (LogFrontend's constructors). The rolling foot acts only on
  // quadruped joints with the identity extrinsic (RollingFoot takes the calf's rate in the base
  // frame and the feet in the body frame, which then differ); otherwise it is left out.
  ContactPipeline(const LogFrontend& frontend, const PipelineOptions& options,
                  std::unique_ptr<contact::ContactDetector> detector = nullptr);
  ContactPipeline(const LogFrontend& frontend, const PipelineOptions& options,
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
  // Per-foot diagnostics since reset() (contact_diagnostics.hpp). Its sources: "truth", the
  // detector's name, or a fallback chain's detectors in order. A single detector "hands over" to
  // none when it cannot decide a foot; a hand-over down a fallback chain is counted with the
  // problem of the detector that had decided the foot until then.
  const ContactDiagnostics& diagnostics() const { return diagnostics_; }

 private:
  LogFrontend frontend_;
  PipelineOptions options_;
  bool rolls_ = false;  // the rolling foot applies (options and front end, above)
  std::unique_ptr<contact::ContactDetector> detector_;
  leg_odometry::RollingFoot rolling_;
  Eigen::Vector3d w_admitted_ = Eigen::Vector3d::Zero();  // the last gyro sample within limits
  FootVelocityDifferentiator velocities_;                 // foot columns without velocity columns
  slip::SlipGuard guard_;
  contact::ContactEstimate contacts_;                    // the source's answer
  std::array<bool, contact::kMaxFeet> down_{};           // the source's contact, last row
  std::array<bool, contact::kMaxFeet> settling_{};       // settleWeight 0 this row
  std::array<double, contact::kMaxFeet> touchdown_t_{};  // when it put the foot down
  StepInput input_;                   // from the contacts, every foot down (the slip check's)
  std::optional<StepInput> reacted_;  // the guard's copy when its reaction changed input_
  StepInput settled_;                 // the guard's answer, the settling feet at p_c = 0
  slip::SlipReport slip_report_;
  Health health_;
  std::optional<double> last_stance_t_;  // last row with a stance foot (or the first row)
  bool silent_ = false;                  // the current stretch has been counted
  const contact::FallbackDetector* chain_ = nullptr;  // detector_, when it is a fallback chain
  ContactDiagnostics diagnostics_;
  // Per foot the source that decided it at the last row: an index of diagnostics_.sources, their
  // count for none, -1 before the first row.
  std::array<int, contact::kMaxFeet> decider_{};
};

}  // namespace legkit
