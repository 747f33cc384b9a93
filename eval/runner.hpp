// Runs an estimator over a whole log and times each step.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "estimation/contact_pipeline.hpp"
#include "estimation/engineering/stationary_init.hpp"
#include "estimation/estimator.hpp"
#include "estimation/health.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/metrics.hpp"
#include "eval/trajectory.hpp"
#include "io/hartley_log.hpp"
#include "io/log.hpp"

namespace legkit::eval {

// Why and where a run stopped early: the estimator threw, or handed back an estimate or a
// covariance the evaluation cannot use (not finite, not positive definite).
struct RunFailure {
  std::string what;     // the reason, e.g. "threw: ..." or "non-finite estimate"
  std::size_t row = 0;  // index of the log row at which it stopped
  double t = 0.0;       // that row's time [s]
  std::string where;    // "file:line" of that row when the log names its file, else empty
};

// One row's slip check on a contact pipeline, in short (slip::SlipReport).
struct SlipSummary {
  int checked = 0;            // stance feet checked
  int slipping = 0;           // of which found slipping
  bool all_slipping = false;  // every foot, or the IMU-vs-legs test
  int outlier = -1;           // foot id of the multi-foot outlier, -1 if none
};

// The share of a run's samples beyond which input the estimator could not use voids the run: an
// estimate resting on less of the log is not reported as healthy (exit 3). Input it could not use:
// IMU samples beyond the sensor's range (the previous one held instead) and updates that failed.
// Every physics scenario, the shipped iCub log and the analytic ones reject none; limits set at the
// edge of their range (gyro_max 0.1 rad/s: 2706 of 3000 samples) or priors at the ends of theirs
// (the TSIF failing 1394 updates in 3000 samples) reject far more than this. 5 % held IMU samples
// is also where integrating a held sample stops being the zero-order hold the noise model covers.
constexpr double kMaxRejectedShare = 0.05;
inline std::uint64_t rejectedInputs(const Health& h) {
  return h[Fault::kGyroRange] + h[Fault::kAccelRange] + h[Fault::kUpdateFailed];
}
// True when rejectedInputs(h) is more than kMaxRejectedShare of `samples`.
inline bool voided(const Health& h, std::size_t samples) {
  return static_cast<double>(rejectedInputs(h)) > kMaxRejectedShare * static_cast<double>(samples);
}

struct RunResult {
  std::string name;
  // How its gyro bias started when the settings asked for the still start (runWithSettings:
  // describeStart), else empty.
  std::string start;
  // One estimate per log row; after a failure, one per row before the failing row.
  Trajectory trajectory;
  double us_per_step = 0;  // mean wall time of Estimator::step [microseconds]
  // For filters (Estimator::covariance()), else empty (same rows as trajectory):
  std::vector<Eigen::Matrix<double, 9, 1>> sigma;  // per row, sqrt of diag P: (theta, v, p)
  // Per row, against the log's ground truth (its pose differentiated for a pose-only truth); NaN
  // on a row without a valid truth (gt_valid = 0); empty without a truth.
  std::vector<double> nees;
  int nees_dof = 0;  // 9, or 6 for a filter without attitude; 0 for no covariance
  Health health;     // the estimator's health at the end of the run (or at its failure)
                     // and, on a pipeline, the pipeline's (Fault::kNoContact)
  // On a contact pipeline (else empty): its contact source ("truth" or the detector's name),
  // per row its contact flags (the detector's usable "contact" answers, or the log's flags; same
  // rows as trajectory, indexed by foot id), and
  // the mean wall time of ContactPipeline::step [microseconds].
  std::string contact_source;
  std::vector<std::array<bool, contact::kMaxFeet>> detected_contact;
  // Per row (same rows as trajectory, indexed by foot id), the feet the estimator was given as
  // stance measurements (StepInput::contacts: after touchdown settling and the slip reaction).
  std::vector<std::array<bool, contact::kMaxFeet>> given_contact;
  std::vector<SlipSummary> slip;  // per row (same rows), whatever the reaction
  std::string slip_reaction;      // "none", "inflate", "drop" or "imu-only"
  // Per foot, who decided its contact, hand-overs, stance, settling, slips (no sources: no
  // pipeline).
  ContactDiagnostics contact_diagnostics;
  double pipeline_us_per_step = 0;
  // The estimator's stance-foot NIS over the run (Estimator::stanceInnovations(); none for an
  // estimator without one).
  std::optional<InnovationStats> stance_nis;
  std::optional<RunFailure> failure;  // set when the run stopped early

  bool failed() const { return failure.has_value(); }
  // Finished, the estimator never had to recover, and it rejected no more input than
  // kMaxRejectedShare of the rows.
  bool ok() const { return !failed() && health.healthy() && !voided(health, trajectory.size()); }
};

// Mean NEES over the rows of one run that have one, divided by its degrees of freedom (1 for a
// consistent filter); NaN when the run has no NEES.
double normalisedAnees(const RunResult& run);

// Resets the estimator to x0, feeds it every row of the log (through the front end) and records
// its estimate after each row, and, for a filter, its standard deviations and (when the log has
// ground truth) its NEES; a pose-only truth's velocity for the NEES is its central difference over
// truth_velocity_window [s] (eval::truthVelocity).
//
// Frames: x0, the recorded trajectory, sigma and NEES are the BASE's (the ground truth's frame).
// With an IMU extrinsic on the front end the estimator runs in the IMU frame: it starts from
// imuFromBase(x0) with row 0's rate, and each estimate and covariance is moved back with
// baseFromImu / baseCovarianceFromImu (estimation/imu_extrinsic_frames.hpp) at the row's
// measured gyro rate w: its bias is not removed (the Estimator interface does not report one;
// 0.01 rad/s of bias at a 0.2 m lever arm is 2 mm/s of base velocity). A log of foot columns
// without velocity columns gets its foot velocities from a FootVelocityDifferentiator run with
// the stance flags (log_frontend.hpp).
//
// Every estimate is checked. If the estimator (or the front end) throws, or returns a non-finite
// estimate, or a covariance that is not finite or whose NEES block is not symmetric positive
// definite, the run stops at that row and result.failure says why and where; runOnLog itself
// never throws for it, so that the caller can go on with other estimators.
//
// gyro_bias (the IMU frame's, as the log's gyro columns): when given, the estimator starts through
// initialise() with it as its gyro bias (stillStart below), not through reset().
RunResult runOnLog(Estimator& estimator, const io::Log& log, const LogFrontend& frontend,
                   const EstimateSample& x0, double truth_velocity_window = kTruthVelocityWindow,
                   const std::optional<Eigen::Vector3d>& gyro_bias = std::nullopt);
// The same on detected contacts: the pipeline is reset, then gives each row's input from the
// estimator's estimate and covariance after the previous row (57.6). Same failure rules (the
// pipeline throwing is a failure of the run). Also records the contact source and the stance
// flags and slip checks per row, and adds the pipeline's health (kNoContact) to the run's.
RunResult runOnLog(Estimator& estimator, const io::Log& log, ContactPipeline& pipeline,
                   const EstimateSample& x0, double truth_velocity_window = kTruthVelocityWindow,
                   const std::optional<Eigen::Vector3d>& gyro_bias = std::nullopt);

// The still window at a log's start (initialisation.gyro_bias: still-window, settings.hpp): the
// log's IMU samples through the estimator manager's engineering::StationaryInitialiser with
// `params` (duration, thresholds, max_wait; `enabled` is the manager's switch and is not read).
// b_g is the window's mean rate in the IMU's frame. A run that starts from it at row 0 uses a
// measurement made over the window, up to `duration` after row 0: as if the robot had stood that
// long before the log began (it stood still then, or there is no window).
struct StillStart {
  Eigen::Vector3d b_g;  // [rad/s]
  double t_end = 0.0;   // the window's last sample [s]
};
// nullopt when no still window ends within params.max_wait of the first row.
std::optional<StillStart> stillStart(const io::Log& log,
                                     const engineering::StationaryInitParams& params);
// What a run that asked for the still start started from, in one line: "gyro bias [x, y, z]
// rad/s, the mean rate of the still window ending at T s (initialisation.gyro_bias)", or that the
// log has no still window and every gyro bias starts at zero.
std::string describeStart(const std::optional<StillStart>& still);

// "file:line" of log row k when the log knows the file it came from, else empty.
std::string rowLocation(const io::Log& log, std::size_t k);

// A run's failure `what` at log row k: its row, time and rowLocation (as runOnLog records it).
RunFailure failureAt(const io::Log& log, std::size_t k, const std::string& what);

// A run's failure reason for an exception its estimator (or front end) threw on a row: "threw: "
// and the message, less the "<Estimator>::step at t = <t>: " the estimators begin it with (the
// failure gives the row's file, line and time; the class is the kit's, not the user's).
std::string threwReason(const std::exception& e);

// Why an estimate (and its covariance, when `cov` is not null) cannot be used, as runOnLog checks
// each row's: "non-finite estimate", "non-finite covariance", "covariance with a negative
// variance on its diagonal"; empty when it can.
std::string unusableEstimate(const EstimateSample& x, const BaseCovariance* cov);

// One line for a failure: "[file:line, ]t = T s (row K): what".
std::string describe(const RunFailure& failure);

// The non-zero counts of a Health, e.g. "3 time gap, 1 state unhealthy (recovered)"; empty when
// every count is zero.
std::string describe(const Health& health);

// The initial state a run starts from (at row 0's time): the log's ground truth at its first
// valid row (gt_valid) when it has one, its velocity from eval::truthVelocity (over
// truth_velocity_window [s]) on a pose-only truth; otherwise at rest at the origin with roll and
// pitch from the first accelerometer sample.
EstimateSample initialState(const io::Log& log,
                            double truth_velocity_window = kTruthVelocityWindow);

// Runs `filter` (reset here) over a log in the reference implementation's text format
// (io/hartley_log.hpp) as the reference's example does (RossHartley/invariant-ekf,
// src/examples/kinematics.cpp): R0 = diag(1, -1, -1), everything else zero at t = 0, a zero IMU
// reading held until the log's first sample (given to the filter as a sample at t = 0: the filter
// never integrates the first sample after a reset), then per record dt from the previous one and
// the kinematics of the feet marked in contact. `after` is called after every record.
void runHartleyLog(Estimator& filter, const io::HartleyLog& log,
                   const std::function<void()>& after = {});

}  // namespace legkit::eval
