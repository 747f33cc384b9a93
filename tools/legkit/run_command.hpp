// `legkit run`, the main job: simulate the default scenario (or read a recorded log), run every
// estimator of the kit on it through the contact pipeline (estimation/contact_pipeline.hpp:
// contacts detected by the kit, slip handling), print the estimator table and under it the
// contact detector's scores, and write the log, the estimates and plots to an output folder.
//   legkit run                          physics trot (MuJoCo), 60 s, Go2-class sensors, seed 1,
//                                       contacts detected, slip handling on
//   legkit run --contact schmitt --slip none
//   legkit run --contact probabilistic   trains the logistic model first (eval/contact_training)
//   legkit run --settle 0                no touchdown settling
//   legkit run --scenario trot          the analytic trot on its true contact flags
//   legkit run --log my_robot.csv --json
//   legkit run --config my_robot.yaml    settings file (legkit config --print); options override it
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "estimation/contact_pipeline.hpp"
#include "eval/contact_scores.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"

namespace legkit::tools {

// The contact source and slip reaction of physics scenarios and recorded logs when the command
// line names none. The analytic scenarios run on their true flags without a slip reaction, as
// they always have; so does a recorded log with contact flags but neither joints nor force
// columns (nothing a detector could read).
constexpr const char* kDefaultContact = "fallback";
constexpr const char* kDefaultSlip = "inflate";
// Touchdown settling [s] on physics scenarios and recorded logs (PipelineOptions::settle_time);
// off on the analytic scenarios, whose contacts are ideal.
constexpr double kDefaultSettle = kRecommendedSettleTime;

// One estimator's line of the table: its run and, when the log has ground truth and the run
// finished, its accuracy; when the log has the true contacts, its detected contacts' scores.
struct RunRow {
  eval::RunResult run;
  std::optional<eval::Metrics> metrics;
  std::optional<eval::ContactScores> contact_scores;
  // The feet's names by foot id ("FL", ...; a robot's own), for the per-foot contact
  // diagnostics; empty: "foot <id>".
  std::vector<std::string> foot_names = {};
};

// The stance-foot NIS check of one run (Estimator::stanceInnovations()): its mean per dimension
// against the bounds below. 1 is consistent. Above `upper` the filter's stance-foot measurements
// are further from its prediction than its covariance allows (over-confident: the stance density
// or the front end's noise too small for this log); below kNisOverCautious far closer
// (over-cautious). `upper` is the larger of the chi-square bound for the run's dimensions,
// chi2inv(0.999, D) / D, and kNisOverConfident: successive updates at 1 kHz are far from
// independent, and the bound alone would flag every real log (see kNisOverConfident).
struct NisCheck {
  double mean = 0.0;  // sum NIS / dimensions
  long updates = 0;
  long dimensions = 0;
  double upper = 0.0;
  double lower = 0.0;
  const char* verdict = "consistent";  // "consistent", "over-confident" or "over-cautious"
};
// The practical bounds on the mean NIS per dimension, measured (chapters/57.11: legkit run's NIS).
constexpr double kNisOverConfident = 3.0;
constexpr double kNisOverCautious = 0.1;
// None for a run without stance-foot updates (an estimator without NIS, no stance foot).
std::optional<NisCheck> checkNis(const eval::RunResult& run);
// The warnings `legkit run` prints to stderr, one per estimator whose NIS is out of its bounds,
// naming the estimator, the ratio and the settings that set it.
std::vector<std::string> nisWarnings(const std::vector<RunRow>& rows);

// The per-foot contact block under the tables: per foot which detectors decided it (shares),
// hand-overs, stance share, touchdowns, samples settled and slipping, the commonest hand-over
// problem; of the first estimator's run when they differ (all of them in summary.json). Nothing
// when no run had a contact pipeline.
void printContactFeet(std::ostream& out, const std::vector<RunRow>& rows);

// The rows of a trajectory that an estimate file at `rate` [Hz] keeps (rate 0: every row): the
// first row, then the first row of each new period 1/rate counted from the first row's time, and
// the last row. Only the files are thinned; the metrics use every row.
std::vector<std::size_t> estimateRows(const std::vector<EstimateSample>& trajectory, double rate);

// The table of `legkit run`: one line per estimator (FAILED for a run that stopped), then under it
// the alignment of its ATE and the distance of its RPE, each failure with its file:line, time and
// reason, and each estimator's non-zero health counts. A metric not computed prints as n/c; a
// truth with masked rows (gt_valid = 0) or a velocity not in the log gets one line saying so.
void printRunTable(std::ostream& out, const std::vector<RunRow>& rows);

// summary.json's "estimators": per estimator its health, ANEES, contact scores and, with a truth,
// its metrics (NaN, "not computed", as null; ATE on the first pose and after the SE(3) and 4-DoF
// alignments, RPE over each distance), the truth's distance, scored and masked rows and where its
// velocity came from; its stance-foot NIS ("stance_nis", checkNis) and per foot its contact
// diagnostics ("feet": [{"foot", "name", "contact": {...}}], ContactDiagnostics).
nlohmann::json toJson(const std::vector<RunRow>& rows);

// The contact detector's table, under the estimator table: precision, recall, F1, touchdown and
// lift-off delays, chatter against the log's true contact. One line for all estimators when their
// runs detected the same flags (a detector that ignores the estimate), else one per estimator.
// Nothing when no row has scores.
void printContactTable(std::ostream& out, const std::vector<RunRow>& rows);
class RunCommand {
 public:
  explicit RunCommand(CLI::App& app);
  RunCommand(const RunCommand&) = delete;  // the options are bound to this object's members
  RunCommand& operator=(const RunCommand&) = delete;

  bool parsed() const { return static_cast<bool>(*command_); }
  // Returns the exit code (tools/legkit/output.hpp); command_line goes into summary.json.
  int run(std::ostream& out, const std::string& command_line) const;

 private:
  CLI::App* command_;
  CLI::Option* scenario_option_;
  CLI::Option* duration_option_;
  CLI::Option* seed_option_;
  CLI::Option* settle_option_;
  CLI::Option* rolling_option_;
  std::string scenario_ = "physics-trot";
  double duration_ = 60.0;
  unsigned seed_ = 1;
  std::string dataset_;  // --dataset: a shipped log; sets log_ (and config_ unless given)
  std::string log_;
  double max_gap_ = 0.0;  // 0: 10 median periods
  std::string out_dir_;
  double estimate_rate_ = 100.0;  // [Hz] of the estimate files; 0: every sample
  std::string contact_;           // empty: kDefaultContact, or "truth" on an analytic scenario
  std::string slip_;              // empty: kDefaultSlip, or "none" on an analytic scenario
  bool rolling_foot_ = true;
  double settle_ = kDefaultSettle;  // [s]; the analytic scenarios' default is 0
  std::string config_;  // settings file (estimation/settings.hpp); empty: the defaults above
  bool json_ = false;
  bool tum_ = false;  // also write the estimates and the truth in TUM format
  bool plots_ = true;
};

}  // namespace legkit::tools
