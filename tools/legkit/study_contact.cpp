#include "study_contact.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "estimation/contact/detectors.hpp"
#include "estimation/contact/foot_force.hpp"
#include "estimation/contact/schmitt_trigger.hpp"
#include "estimation/contact_pipeline.hpp"
#include "estimation/estimators.hpp"
#include "estimation/slip/slip_guard.hpp"
#include "estimation/slip/terrain.hpp"
#include "eval/contact_scores.hpp"
#include "eval/contact_training.hpp"
#include "eval/metrics.hpp"
#include "eval/monte_carlo.hpp"
#include "eval/runner.hpp"
#include "model/quadruped.hpp"
#include "model/quadruped_inertia.hpp"
#include "output.hpp"
#include "scenarios.hpp"
#include "sim/physics_simulator.hpp"
#include "study_filters.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kFeet = 4;
constexpr const char* kLegs[kFeet] = {"FL", "FR", "RL", "RR"};
constexpr int kTraceFoot = 1;  // FR: the foot over the ice patch, and the figures' foot
// A true slip (57.7): the contact point slides faster than kSlipSpeed for at least kSlipHold.
constexpr double kSlipSpeed = 0.1;  // [m/s]
constexpr double kSlipHold = 0.02;  // [s]
// A detected slip onset belongs to a true slip within this margin of it [s].
constexpr double kSlipMargin = 0.05;
// A detected onset this close to a sample of a slide too short to be a true slip is not false.
constexpr double kShortSlide = 0.02;  // [s]

std::ostringstream newCsv() {
  std::ostringstream csv;
  csv << std::setprecision(8);
  return csv;
}

// The scenario for a study: `duration` seconds, lengthened to end 1 s after a push it would cut.
sim::PhysicsOptions studyOptions(const std::string& scenario, double duration, unsigned seed) {
  sim::PhysicsOptions o = sim::PhysicsOptions::forScenario(scenario);
  o.duration = duration;
  for (const sim::Push& p : o.scenario.pushes) {
    o.duration = std::max(o.duration, p.start + p.duration + 1.0);
  }
  o.seed = seed;
  return o;
}

contact::DetectorContext detectorContext(const sim::PhysicsScenario& s,
                                         const contact::LogisticModel& logistic) {
  contact::DetectorContext c;
  c.geometry = model::QuadrupedGeometry::go2();
  c.inertia = model::QuadrupedInertia::go2();
  c.gait = eval::plannedGait(s);  // the controller's clock, as its planner would publish it
  c.logistic = logistic;
  return c;
}

// What one filter did over a log with its contacts from a pipeline.
struct PipelineRun {
  eval::Trajectory trajectory;            // per row
  std::vector<eval::FootFlags> detected;  // per row: the usable answers that say contact
  long undecided = 0;                     // foot samples whose answer was not usable
  // Per row, when recorded: each foot's d2 (NaN when not checked) and slipping flag.
  std::vector<std::array<double, kFeet>> d2;
  std::vector<std::array<bool, kFeet>> slipping;
  std::vector<bool> all_slipping;
  double threshold = kNaN;  // chi2_3(alpha)
};

// The terrain classifier of 57.7 fed along a run: each row's slip check and the ground forces
// estimated from the joint torques (FootForceFromTorque, with the filter's previous estimate),
// with the classifier's guards for estimated forces (slip::estimatedForceParams: a ratio counts
// only 30 ms into a loaded stance, an onset only once its slip has held 5 ms).
struct TerrainWatch {
  contact::FootForceFromTorque forces{model::QuadrupedGeometry::go2(),
                                      model::QuadrupedInertia::go2()};
  slip::TerrainClassifier classifier{slip::estimatedForceParams()};
};

// Runs `filter` over the log, each row's input from the pipeline given the filter's estimate and
// covariance after the previous row (57.6's rule: detect with the last estimate; the pipeline's
// slip check, 57.7, against that same estimate), recording the slip checks when `slips` and
// feeding `terrain` when given.
PipelineRun runPipeline(const io::Log& log, Estimator& filter, ContactPipeline& pipeline,
                        bool slips, TerrainWatch* terrain = nullptr) {
  PipelineRun run;
  const std::size_t n = log.rows.size();
  run.trajectory.reserve(n);
  run.detected.reserve(n);
  EstimateSample x = eval::initialState(log);
  filter.reset(x);
  pipeline.reset();
  std::optional<BaseCovariance> P = filter.covariance();
  for (std::size_t k = 0; k < n; ++k) {
    const io::LogRow& row = log.rows[k];
    const double dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
    filter.step(pipeline.step(row, dt, x, P));
    if (terrain) {
      const contact::BaseFeedback base = contact::feedbackFrom(x);
      const auto f = terrain->forces.estimate(pipeline.frontend().signals(row, dt, base));
      terrain->classifier.update(pipeline.slipReport(), f.data(), kFeet, dt);
    }
    x = filter.estimate();
    P = filter.covariance();
    run.trajectory.push_back(x);
    eval::FootFlags flags{};
    const contact::ContactEstimate& c = pipeline.contacts();
    for (int i = 0; i < kFeet; ++i) {
      flags[i] = c.feet[i].usable() && c.feet[i].contact;
      run.undecided += !c.feet[i].usable();
    }
    run.detected.push_back(flags);
    if (slips) {
      const slip::SlipReport& report = pipeline.slipReport();
      run.threshold = report.threshold;
      std::array<double, kFeet> d2;
      d2.fill(kNaN);
      std::array<bool, kFeet> slipping{};
      for (int j = 0; j < report.num_feet; ++j) {
        const slip::FootSlip& f = report.feet[j];
        if (f.foot < 0 || f.foot >= kFeet) continue;
        d2[f.foot] = f.d2;
        slipping[f.foot] = f.slipping || report.all_slipping;
      }
      run.d2.push_back(d2);
      run.slipping.push_back(slipping);
      run.all_slipping.push_back(report.all_slipping);
    }
  }
  return run;
}

std::unique_ptr<ContactPipeline> makePipeline(
    const io::Log& log, const sim::PhysicsOptions& o, const std::string& source,
    const contact::DetectorContext& context,
    slip::SlipReaction reaction = slip::SlipReaction::kNone) {
  PipelineOptions options;
  options.contact = source;
  options.slip = reaction;
  std::unique_ptr<contact::ContactDetector> detector;
  if (source != "truth") detector = contact::makeDetector(source, context);
  return std::make_unique<ContactPipeline>(log.layout, model::QuadrupedKinematics(),
                                           matchedFrontendNoise(o), options, std::move(detector));
}

std::vector<double> times(const io::Log& log) {
  std::vector<double> t;
  t.reserve(log.rows.size());
  for (const io::LogRow& r : log.rows) t.push_back(r.t);
  return t;
}

std::vector<eval::FootFlags> trueContacts(const io::Log& log) {
  std::vector<eval::FootFlags> truth(log.rows.size(), eval::FootFlags{});
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    for (int i = 0; i < kFeet; ++i) truth[k][i] = log.rows[k].gt_feet[i].contact;
  }
  return truth;
}

sim::PhysicsResult simulate(const sim::PhysicsOptions& o) {
  sim::PhysicsResult r = sim::simulatePhysics(o);
  if (r.log.rows.size() < 2) {
    throw eval::RunFailedError(o.scenario.name + ": " + describeFall(r.status) +
                               " before a second row");
  }
  return r;
}

std::string scenarioLabel(const sim::PhysicsOptions& o, const sim::PhysicsResult& r) {
  std::string label = o.scenario.name;
  if (r.status.fell) label += " (fell at " + formatFixed(r.status.time, 2) + " s)";
  return label;
}

Progress stderrProgress() {
  return Progress(std::cerr, isatty(fileno(stderr)) != 0);
}

// The true slips of one foot: the stretches where its contact point slides faster than
// kSlipSpeed for at least kSlipHold, as [begin, end) times.
std::vector<std::pair<double, double>> trueSlips(const io::Log& log, int foot) {
  std::vector<std::pair<double, double>> slips;
  double begin = kNaN;  // start of the current stretch, NaN outside one
  for (std::size_t k = 0; k <= log.rows.size(); ++k) {
    const bool sliding = k < log.rows.size() && log.rows[k].gt_feet[foot].slip_speed > kSlipSpeed;
    if (sliding && std::isnan(begin)) begin = log.rows[k].t;
    if (!sliding && !std::isnan(begin)) {
      const double end = k < log.rows.size() ? log.rows[k].t : log.rows.back().t;
      if (end - begin >= kSlipHold - 1e-9) slips.emplace_back(begin, end);
      begin = kNaN;
    }
  }
  return slips;
}

// The friction of the ground under foot `foot` at row r (its true position: the true base pose and
// the leg's forward kinematics): the last patch that holds it, else the ground's.
double frictionUnderFoot(const sim::Terrain& terrain, const io::LogRow& r, int foot) {
  static const model::QuadrupedKinematics kinematics;
  const Eigen::Vector3d p =
      r.gt_p + r.gt_q * kinematics.footPosition(foot, r.q.segment<3>(3 * foot));
  double mu = terrain.friction;
  for (const sim::FrictionPatch& patch : terrain.patches) {
    if (p.x() >= patch.min.x() && p.x() <= patch.max.x() && p.y() >= patch.min.y() &&
        p.y() <= patch.max.y()) {
      mu = patch.friction;
    }
  }
  return mu;
}

struct SlipScores {
  int slips = 0;             // true slips, all feet
  int detected = 0;          // of them, detected within their margin
  double delay_mean = kNaN;  // first detection - true onset [ms]
  double delay_p95 = kNaN;   // nearest rank [ms]
  // Detected onsets outside every true slip's margin, per minute: at a short slide (the foot's
  // slip speed above kSlipSpeed within kShortSlide of the onset, for less than kSlipHold), or
  // false (no such sample).
  double short_slides_per_min = 0.0;
  double false_alarms_per_min = 0.0;
};

// The slip detector's flags against the true slips (kSlipSpeed for kSlipHold), per foot.
SlipScores scoreSlips(const io::Log& log, const PipelineRun& run) {
  SlipScores s;
  std::vector<double> delays;
  int false_alarms = 0, short_slides = 0;
  for (int i = 0; i < kFeet; ++i) {
    const auto slips = trueSlips(log, i);
    s.slips += static_cast<int>(slips.size());
    for (const auto& [begin, end] : slips) {
      for (std::size_t k = 0; k < log.rows.size(); ++k) {
        const double t = log.rows[k].t;
        if (t < begin - kSlipMargin || !run.slipping[k][i]) continue;
        if (t > end + kSlipMargin) break;
        delays.push_back(1e3 * (t - begin));
        break;
      }
    }
    for (std::size_t k = 1; k < log.rows.size(); ++k) {
      if (!run.slipping[k][i] || run.slipping[k - 1][i]) continue;
      const double t = log.rows[k].t;
      const bool explained = std::any_of(slips.begin(), slips.end(), [t](const auto& sl) {
        return t >= sl.first - kSlipMargin && t <= sl.second + kSlipMargin;
      });
      if (explained) continue;
      bool slide = false;
      for (std::size_t j = k; j > 0 && log.rows[j].t >= t - kShortSlide; --j) {
        slide = slide || log.rows[j].gt_feet[i].slip_speed > kSlipSpeed;
      }
      for (std::size_t j = k; j < log.rows.size() && log.rows[j].t <= t + kShortSlide; ++j) {
        slide = slide || log.rows[j].gt_feet[i].slip_speed > kSlipSpeed;
      }
      (slide ? short_slides : false_alarms) += 1;
    }
  }
  s.detected = static_cast<int>(delays.size());
  if (!delays.empty()) {
    double sum = 0.0;
    for (const double d : delays) sum += d;
    s.delay_mean = sum / static_cast<double>(delays.size());
    std::sort(delays.begin(), delays.end());
    const auto rank = static_cast<std::size_t>(std::ceil(0.95 * delays.size()));
    s.delay_p95 = delays[std::max<std::size_t>(rank, 1) - 1];
  }
  const double minutes = (log.rows.back().t - log.rows.front().t) / 60.0;
  s.false_alarms_per_min = false_alarms / minutes;
  s.short_slides_per_min = short_slides / minutes;
  return s;
}

}  // namespace

StudyContact::StudyContact(CLI::App& study) {
  contact_ = study.add_subcommand(
      "contact", "Every contact detector on every physics scenario vs the true contact (57.6)");
  slip_ = study.add_subcommand(
      "slip",
      "Slip detection and reactions on ice, every filter on true vs detected contacts (57.7)");
  for (CLI::App* c : {contact_, slip_}) {
    c->add_option("--seed", seed_, "Seed of the simulated runs")
        ->check(seedNumber())
        ->capture_default_str();
    // A second at the least: a touchdown and a lift-off of the trot (0, -1 and NaN once fell
    // back to the default); at most the longest simulated run.
    c->add_option("--duration", duration_,
                  "Simulated time per scenario [s], 1..3600 (runs with a push end 1 s after it "
                  "at least); default: the study's own")
        ->check(finiteRange(1.0, kMaxSimulatedSeconds));
    c->add_option("--out", out_dir_, "Output folder (default legkit-out/study-<name>)")
        ->check(nonEmptyName());
    c->add_flag("!--no-plots", plots_, "Do not draw the PNG figures");
    // Each name checked by subset() (run): '' would have meant every scenario.
    c->add_option("--scenarios", scenarios_,
                  "Only these of the study's scenarios (comma-separated; default: all of them)")
        ->check(nonEmptyName())
        ->delimiter(',');
  }
  contact_
      ->add_option("--filter", filter_,
                   "The estimator run on each detector's contacts (its estimate is the "
                   "detectors' base feedback)")
      ->check(CLI::IsMember(estimatorNames()))
      ->capture_default_str();
  std::vector<std::string> sources = {"truth"};
  for (const std::string& name : contact::detectorNames()) sources.push_back(name);
  slip_
      ->add_option("--contact", contact_source_,
                   "Contact source of the slip runs: truth or a detector name")
      ->check(CLI::IsMember(sources))
      ->capture_default_str();
  slip_
      ->add_option("--filters", filters_,
                   "Only these filters (comma-separated; default: every filter)")
      ->check(nonEmptyName())
      ->delimiter(',');
}

namespace {

// `chosen` when given, each one of `all`; else `all`. Throws UsageError naming the unknown one.
std::vector<std::string> subset(const std::vector<std::string>& all,
                                const std::vector<std::string>& chosen, const char* option) {
  if (chosen.empty()) return all;
  for (const std::string& c : chosen) {
    if (std::find(all.begin(), all.end(), c) != all.end()) continue;
    std::string known;
    for (const std::string& a : all) known += (known.empty() ? "" : ", ") + a;
    throw UsageError(std::string(option) + ": unknown '" + c + "' (known: " + known + ")");
  }
  return chosen;
}

}  // namespace

int StudyContact::run(std::ostream& out) const {
  try {
    return *contact_ ? contact(out) : slip(out);
  } catch (const eval::RunFailedError& e) {
    std::cerr << "legkit study: " << e.what() << "\n";
    return kExitUnhealthy;
  }
}

// Every detector (contact::detectorNames()) on every physics scenario, each feeding `filter_` on
// its own contacts through the contact pipeline, scored against gt_feet[].contact.
int StudyContact::contact(std::ostream& out) const {
  const double duration = duration_ > 0 ? duration_ : 10.0;
  // The options first: an unknown scenario once waited for the training below (8 s).
  const std::vector<std::string> scenarios =
      subset(sim::physicsScenarioNames(), scenarios_, "--scenarios");
  const fs::path dir = out_dir_.empty() ? fs::path("legkit-out/study-contact") : fs::path(out_dir_);
  makeOutputFolder(dir);
  try {
    makeEstimator(filter_);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--filter: ") + e.what());
  }
  Progress progress = stderrProgress();
  progress.run("contact, training the logistic model", 0, 1);
  // Trained on its own runs (seeds seed + 1000.., eval/contact_training.hpp), not these.
  const contact::LogisticModel logistic = eval::trainContactModel(seed_);
  const std::vector<std::string> detectors = contact::detectorNames();

  std::ostringstream csv = newCsv(), trace = newCsv();
  csv << "# seed " << seed_ << " duration " << duration << " filter " << filter_ << '\n'
      << "scenario,detector,fell,precision,recall,f1,touchdown_delay_mean_ms,"
         "touchdown_delay_p95_ms,liftoff_delay_mean_ms,liftoff_delay_p95_ms,chatter_per_min,"
         "touchdowns,liftoffs,missed_touchdowns,missed_liftoffs,spurious_toggles,"
         "undecided_percent,position_rmse,velocity_rmse\n";
  std::vector<std::vector<std::string>> table = {
      {"scenario", "detector", "precision", "recall", "F1", "TD delay", "TD p95", "LO delay",
       "LO p95", "chatter", "undecided", "pos RMSE"},
      {"", "", "", "", "", "[ms]", "[ms]", "[ms]", "[ms]", "[1/min]", "[%]", "[m]"}};
  // Per detector over the scenarios: sums of F1, touchdown delay, lift-off delay, chatter.
  std::map<std::string, std::array<double, 4>> sums;
  std::map<std::string, std::array<int, 4>> counts;

  const contact::SchmittParams schmitt = contact::DetectorContext{}.schmitt;  // the sensor's
  const sim::PhysicsOptions trot = studyOptions("physics-trot", duration, seed_);
  const double trace_to = std::min(5.0, trot.duration);
  const double trace_from = std::max(0.0, trace_to - 2.0);
  trace << "# physics-trot foot " << kLegs[kTraceFoot] << " f_high " << schmitt.f_high << " f_low "
        << schmitt.f_low << '\n';
  std::vector<std::vector<double>> trace_columns;  // per detector: contact, force per row
  std::vector<double> trace_t, trace_force, trace_fn, trace_truth;

  int done = 0;
  const int total = static_cast<int>(scenarios.size() * detectors.size());
  for (const std::string& name : scenarios) {
    const sim::PhysicsOptions o = studyOptions(name, duration, seed_);
    const sim::PhysicsResult sim = simulate(o);
    const io::Log& log = sim.log;
    const std::vector<double> t = times(log);
    const std::vector<eval::FootFlags> truth = trueContacts(log);
    const contact::DetectorContext context = detectorContext(o.scenario, logistic);
    const bool traced = name == "physics-trot";
    if (traced) {
      for (const io::LogRow& r : log.rows) {
        if (r.t < trace_from || r.t > trace_to) continue;
        trace_t.push_back(r.t);
        trace_force.push_back(r.force[kTraceFoot]);
        trace_fn.push_back(r.gt_feet[kTraceFoot].normal_force);
        trace_truth.push_back(r.gt_feet[kTraceFoot].contact);
      }
    }
    for (const std::string& detector : detectors) {
      progress.run("contact, " + name + ", " + detector, done++, total);
      const std::unique_ptr<ContactPipeline> pipeline = makePipeline(log, o, detector, context);
      const std::unique_ptr<Estimator> filter = makeEstimator(filter_);
      const PipelineRun run = runPipeline(log, *filter, *pipeline, false);
      const eval::ContactScores s = eval::scoreContacts(t, run.detected, truth, kFeet);
      const eval::Metrics m = eval::compare(log, run.trajectory);
      const double undecided = 100.0 * run.undecided / (kFeet * static_cast<double>(t.size()));
      csv << name << ',' << detector << ',' << sim.status.fell << ',' << s.precision << ','
          << s.recall << ',' << s.f1 << ',' << s.touchdown_delay_mean << ','
          << s.touchdown_delay_p95 << ',' << s.liftoff_delay_mean << ',' << s.liftoff_delay_p95
          << ',' << s.chatter_per_min << ',' << s.touchdowns << ',' << s.liftoffs << ','
          << s.missed_touchdowns << ',' << s.missed_liftoffs << ',' << s.spurious_toggles << ','
          << undecided << ',' << m.position_rmse << ',' << m.velocity_rmse << '\n';
      table.push_back({detector == detectors.front() ? scenarioLabel(o, sim) : "", detector,
                       formatFixed(s.precision, 3), formatFixed(s.recall, 3), formatFixed(s.f1, 3),
                       formatFixed(s.touchdown_delay_mean, 1),
                       formatFixed(s.touchdown_delay_p95, 1), formatFixed(s.liftoff_delay_mean, 1),
                       formatFixed(s.liftoff_delay_p95, 1), formatFixed(s.chatter_per_min, 1),
                       formatFixed(undecided, 1), formatFixed(m.position_rmse, 3)});
      const std::array<double, 4> values = {s.f1, s.touchdown_delay_mean, s.liftoff_delay_mean,
                                            s.chatter_per_min};
      for (int j = 0; j < 4; ++j) {
        if (std::isnan(values[j])) continue;
        sums[detector][j] += values[j];
        ++counts[detector][j];
      }
      if (traced) {
        std::vector<double> contact_column;
        for (std::size_t k = 0; k < log.rows.size(); ++k) {
          if (log.rows[k].t < trace_from || log.rows[k].t > trace_to) continue;
          contact_column.push_back(run.detected[k][kTraceFoot]);
        }
        trace_columns.push_back(contact_column);
      }
    }
  }
  progress.clear();

  trace << "t,force,gt_fn,gt_contact";
  for (const std::string& d : detectors) trace << ',' << d;
  trace << '\n';
  for (std::size_t k = 0; k < trace_t.size(); ++k) {
    trace << trace_t[k] << ',' << trace_force[k] << ',' << trace_fn[k] << ',' << trace_truth[k];
    for (const std::vector<double>& c : trace_columns) trace << ',' << c[k];
    trace << '\n';
  }

  out << "Contact detectors against the physics' true contact (" << duration
      << " s per scenario, seed " << seed_ << "; each detector sees the estimate of " << filter_
      << " running on its own contacts; TD touchdown, LO lift-off: delay of the detected toggle "
         "matched within +-100 ms, mean and 95th percentile; chatter: detected toggles matching "
         "no true one; undecided: samples where the detector could not answer)\n\n";
  printTable(out, table);
  out << "\nPer detector, mean over the scenarios:\n\n";
  std::vector<std::vector<std::string>> summary = {
      {"detector", "F1", "TD delay [ms]", "LO delay [ms]", "chatter [1/min]"}};
  for (const std::string& d : detectors) {
    summary.push_back({d});
    for (int j = 0; j < 4; ++j) {
      summary.back().push_back(
          formatFixed(counts[d][j] ? sums[d][j] / counts[d][j] : kNaN, j == 0 ? 3 : 1));
    }
  }
  printTable(out, summary);
  writeAtomically(dir / "contact.csv", [&](std::ostream& f) { f << csv.str(); });
  writeAtomically(dir / "contact-trace.csv", [&](std::ostream& f) { f << trace.str(); });
  out << "tables: " << (dir / "contact.csv").string() << ", "
      << (dir / "contact-trace.csv").string() << '\n';
  if (plots_) {
    const std::string failed = plot("57.6-contact.py", {dir.string()});
    out << (failed.empty() ? "figures: " + (dir / "57.6-contact-trace.png").string() + ", " +
                                 (dir / "57.6-contact-f1-delay.png").string()
                           : failed)
        << '\n';
    if (plotFailed(failed)) return kExitInput;
  }
  return 0;
}

// The slip detector and its reactions (estimation/slip/slip_guard.hpp) on the ice scenarios and
// the dry trot, every filter on contacts from `contact_source_`; then every filter on the dry
// trot with true contacts and with detected ones.
int StudyContact::slip(std::ostream& out) const {
  const double duration = duration_ > 0 ? duration_ : 10.0;
  const std::vector<std::string> scenarios =
      subset({"physics-ice", "physics-ice-push", "physics-ice-aware", "physics-trot"}, scenarios_,
             "--scenarios");
  const fs::path dir = out_dir_.empty() ? fs::path("legkit-out/study-slip") : fs::path(out_dir_);
  const std::vector<slip::SlipReaction> reactions = {
      slip::SlipReaction::kNone, slip::SlipReaction::kInflate, slip::SlipReaction::kDrop,
      slip::SlipReaction::kImuOnly};
  const std::vector<std::string> filters = subset(filterNames(), filters_, "--filters");
  const std::vector<std::string> detectors = contact::detectorNames();
  if (contact_source_ != "truth" &&
      std::find(detectors.begin(), detectors.end(), contact_source_) == detectors.end()) {
    throw UsageError("--contact: neither truth nor a detector: " + contact_source_);
  }
  makeOutputFolder(dir);  // after the options' checks: a bad one leaves no folder
  Progress progress = stderrProgress();
  progress.run("slip, training the logistic model", 0, 1);
  const contact::LogisticModel logistic = eval::trainContactModel(seed_);

  std::ostringstream csv = newCsv(), trace = newCsv();
  csv << "# seed " << seed_ << " duration " << duration << " contact " << contact_source_ << '\n'
      << "scenario,filter,reaction,position_rmse,velocity_rmse,slips,detected,delay_mean_ms,"
         "delay_p95_ms,short_slides_per_min,false_alarms_per_min\n";
  std::vector<std::vector<std::string>> detection = {
      {"scenario", "filter", "true slips", "detected", "delay [ms]", "p95 [ms]",
       "at short slides [1/min]", "false alarms [1/min]"}};
  std::vector<std::vector<std::string>> accuracy = {
      {"scenario", "filter", "pos RMSE [m]:", "", "", "", "vel RMSE [m/s]:", "", "", ""},
      {"", "", "none", "inflate", "drop", "imu-only", "none", "inflate", "drop", "imu-only"}};
  std::ostringstream terrain_csv = newCsv();
  terrain_csv << "# seed " << seed_ << " duration " << duration << " contact " << contact_source_
              << " filter invariant-ekf\n"
              << "scenario,true_mu,class,mu_hat,mu_lower_bound,onsets,slip_rate,slip_fraction\n";
  std::vector<std::vector<std::string>> terrain_table = {{"scenario", "true mu", "class", "mu_hat",
                                                          "mu lower bound", "onsets",
                                                          "slip rate [1/s]", "slipping [%]"}};
  int done = 0;
  const int total = static_cast<int>(scenarios.size() * filters.size() * reactions.size());
  for (const std::string& name : scenarios) {
    const sim::PhysicsOptions o = studyOptions(name, duration, seed_);
    const sim::PhysicsResult sim = simulate(o);
    const io::Log& log = sim.log;
    const contact::DetectorContext context = detectorContext(o.scenario, logistic);
    for (const std::string& f : filters) {
      std::vector<std::string> row = {f == filters.front() ? scenarioLabel(o, sim) : "", f};
      std::vector<std::string> velocity;
      for (const slip::SlipReaction reaction : reactions) {
        progress.run("slip, " + name + ", " + f, done++, total);
        const std::unique_ptr<ContactPipeline> pipeline =
            makePipeline(log, o, contact_source_, context, reaction);
        const std::unique_ptr<Estimator> filter = makeEstimator(f);
        TerrainWatch terrain;
        const bool watched = reaction == slip::SlipReaction::kNone && f == "invariant-ekf";
        const PipelineRun run =
            runPipeline(log, *filter, *pipeline, true, watched ? &terrain : nullptr);
        const eval::Metrics m = eval::compare(log, run.trajectory);
        if (watched) {
          const slip::TerrainClassifier& c = terrain.classifier;
          std::string mu = formatFixed(o.scenario.terrain.friction, 2);
          for (const sim::FrictionPatch& patch : o.scenario.terrain.patches) {
            mu += " (" + formatFixed(patch.friction, 2) + " patch)";
          }
          terrain_csv << name << ',' << mu << ',' << slip::terrainClassName(c.terrain()) << ','
                      << c.frictionEstimate() << ',' << c.frictionLowerBound() << ',' << c.onsets()
                      << ',' << c.slipRate() << ',' << c.slipFraction() << '\n';
          terrain_table.push_back({scenarioLabel(o, sim), mu, slip::terrainClassName(c.terrain()),
                                   formatFixed(c.frictionEstimate(), 3),
                                   formatFixed(c.frictionLowerBound(), 3),
                                   std::to_string(c.onsets()), formatFixed(c.slipRate(), 2),
                                   formatFixed(100.0 * c.slipFraction(), 1)});
        }
        const SlipScores s = scoreSlips(log, run);
        csv << name << ',' << f << ',' << slip::slipReactionName(reaction) << ',' << m.position_rmse
            << ',' << m.velocity_rmse << ',' << s.slips << ',' << s.detected << ',' << s.delay_mean
            << ',' << s.delay_p95 << ',' << s.short_slides_per_min << ',' << s.false_alarms_per_min
            << '\n';
        row.push_back(formatFixed(m.position_rmse, 3));
        velocity.push_back(formatFixed(m.velocity_rmse, 3));
        if (reaction != slip::SlipReaction::kNone) continue;
        // Detection is scored without a reaction: what the detector sees of an untouched filter.
        detection.push_back(
            {f == filters.front() ? scenarioLabel(o, sim) : "", f, std::to_string(s.slips),
             std::to_string(s.detected), formatFixed(s.delay_mean, 1), formatFixed(s.delay_p95, 1),
             formatFixed(s.short_slides_per_min, 1), formatFixed(s.false_alarms_per_min, 1)});
        if (name == "physics-ice" && f == "invariant-ekf") {
          trace << "# physics-ice foot " << kLegs[kTraceFoot] << " filter " << f << " threshold "
                << run.threshold << '\n'
                << "t,mu,slip_speed,d2,slipping\n";
          for (std::size_t k = 0; k < log.rows.size(); ++k) {
            const io::LogRow& r = log.rows[k];
            trace << r.t << ',' << frictionUnderFoot(o.scenario.terrain, r, kTraceFoot) << ','
                  << r.gt_feet[kTraceFoot].slip_speed << ',' << run.d2[k][kTraceFoot] << ','
                  << run.slipping[k][kTraceFoot] << '\n';
          }
        }
      }
      row.insert(row.end(), velocity.begin(), velocity.end());
      accuracy.push_back(row);
    }
  }

  // Every filter on the dry trot, true contacts against detected ones (no slip reaction).
  const std::vector<std::string> sources = {"truth", "schmitt", "probabilistic", "fallback"};
  const sim::PhysicsOptions o = studyOptions("physics-trot", duration, seed_);
  const sim::PhysicsResult sim = simulate(o);
  const contact::DetectorContext context = detectorContext(o.scenario, logistic);
  std::vector<std::vector<std::string>> sources_table = {{"filter"}, {""}};
  for (const std::string& s : sources) {
    sources_table[0].push_back(s);
    sources_table[1].push_back("pos [m], vel [m/s]");
  }
  std::ostringstream sources_csv = newCsv();
  sources_csv << "# physics-trot seed " << seed_ << " duration " << o.duration << '\n'
              << "source,filter,position_rmse,velocity_rmse\n";
  for (const std::string& f : filters) {
    sources_table.push_back({f});
    for (const std::string& source : sources) {
      const std::unique_ptr<ContactPipeline> pipeline = makePipeline(sim.log, o, source, context);
      const std::unique_ptr<Estimator> filter = makeEstimator(f);
      const PipelineRun run = runPipeline(sim.log, *filter, *pipeline, false);
      const eval::Metrics m = eval::compare(sim.log, run.trajectory);
      sources_csv << source << ',' << f << ',' << m.position_rmse << ',' << m.velocity_rmse << '\n';
      sources_table.back().push_back(formatFixed(m.position_rmse, 3) + ", " +
                                     formatFixed(m.velocity_rmse, 3));
    }
  }
  progress.clear();

  out << "Slip detection (" << duration << " s per scenario, seed " << seed_ << ", contacts from "
      << contact_source_ << "; a true slip: the contact point slides faster than " << kSlipSpeed
      << " m/s for " << 1e3 * kSlipHold << " ms or more; delay: first detection within "
      << 1e3 * kSlipMargin << " ms of it; other detected onsets are at a short slide when the "
      << "foot slid faster than " << kSlipSpeed << " m/s within " << 1e3 * kShortSlide
      << " ms of it, else false alarms; scored with the reaction 'none')\n\n";
  printTable(out, detection);
  out << "\nEvery filter with each slip reaction:\n\n";
  printTable(out, accuracy);
  out << "\nTerrain classes at the end of each run (invariant-ekf, reaction none; forces from the "
         "joint torques: a ratio counts 30 ms into a loaded stance, a slip onset once its slip has "
         "held 5 ms; slip rate per second and share of stance foot-time slipping):\n\n";
  printTable(out, terrain_table);
  out << "\nEvery filter on physics-trot, true against detected contacts (no slip reaction):\n\n";
  printTable(out, sources_table);
  writeAtomically(dir / "slip.csv", [&](std::ostream& f) { f << csv.str(); });
  writeAtomically(dir / "slip-sources.csv", [&](std::ostream& f) { f << sources_csv.str(); });
  writeAtomically(dir / "slip-terrain.csv", [&](std::ostream& f) { f << terrain_csv.str(); });
  writeAtomically(dir / "slip-trace.csv", [&](std::ostream& f) { f << trace.str(); });
  out << "tables: " << (dir / "slip.csv").string() << ", " << (dir / "slip-sources.csv").string()
      << ", " << (dir / "slip-terrain.csv").string() << ", " << (dir / "slip-trace.csv").string()
      << '\n';
  if (plots_) {
    const std::string failed = plot("57.7-slip.py", {dir.string()});
    out << (failed.empty() ? "figure: " + (dir / "57.7-slip.png").string() : failed) << '\n';
    if (plotFailed(failed)) return kExitInput;
  }
  return 0;
}

}  // namespace legkit::tools
