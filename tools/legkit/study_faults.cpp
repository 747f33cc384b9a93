#include "study_faults.hpp"

#include <cmath>
#include <functional>
#include <iomanip>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "estimation/contact/detectors.hpp"
#include "estimation/estimators.hpp"
#include "eval/contact_training.hpp"
#include "eval/fault_injection.hpp"
#include "eval/runner.hpp"
#include "sim/physics_simulator.hpp"
#include "validators.hpp"

namespace legkit::tools {

namespace {

constexpr double kDuration = 3.0;  // stand 0-1 s, trot from 1 s
constexpr double kOnset = 1.5;     // every fault but the drift starts here [s]
constexpr double kRadToDeg = 180.0 / M_PI;

struct FaultCase {
  const char* name;
  std::function<io::Log(const io::Log&)> inject;
  bool has_answer;  // the monitor has an answer to compare against the run without it
};

// "alarm at t s, ..." for every alarm raised, "-" when none.
std::string alarms(const eval::MonitoredRun& r) {
  std::string s;
  for (int a = 0; a < engineering::kNumAlarms; ++a) {
    if (r.report.count[a] == 0) continue;
    std::ostringstream os;
    os << std::fixed << std::setprecision(3) << r.detected_at[a];
    s += (s.empty() ? "" : ", ") +
         std::string(engineering::alarmName(static_cast<engineering::Alarm>(a))) + " at " +
         os.str() + " s";
  }
  return s.empty() ? "-" : s;
}

// "position m / attitude deg / velocity m/s / position sigma m" maxima over the run, then the
// estimator's and the pipeline's faults when there were any.
std::string errors(const eval::MonitoredRun& r) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(4) << r.maxOver(r.position_error, 0, kDuration) << " m / "
     << std::setprecision(2) << r.maxOver(r.attitude_error, 0, kDuration) * kRadToDeg << " deg / "
     << r.maxOver(r.velocity_error, 0, kDuration) << " m/s / " << std::setprecision(4)
     << r.maxOver(r.position_sigma, 0, kDuration) << " m";
  if (!r.finite) os << " (not finite)";
  const std::string health = eval::describe(r.health);
  if (!health.empty()) os << "; " << health;
  return os.str();
}

}  // namespace

StudyFaults::StudyFaults(CLI::App& study)
    : faults_(study.add_subcommand(
          "faults",
          "Section 57.9's faults on a 3 s physics trot: the monitor's alarms and "
          "answers (chapter 57.9's troubleshooting table)")) {
  faults_->add_option("--seed", seed_, "Seed of the physics trot")
      ->check(seedNumber())
      ->capture_default_str();
  faults_->add_option("--filter", filter_, "The estimator run on the recommended contact chain")
      ->check(CLI::IsMember(estimatorNames()))
      ->capture_default_str();
}

int StudyFaults::run(std::ostream& out) const {
  sim::PhysicsOptions o = sim::PhysicsOptions::forScenario("physics-trot");
  o.duration = kDuration;
  o.seed = seed_;
  const io::Log log = sim::simulatePhysics(o).log;
  PipelineOptions po;  // what `legkit run` uses on physics
  po.contact = "fallback";
  po.slip = slip::SlipReaction::kInflate;
  po.settle_time = kRecommendedSettleTime;
  contact::DetectorContext context;
  context.gait = eval::plannedGait(o.scenario);
  auto monitored = [&](const io::Log& faulty, bool degrade) {
    ContactPipeline pipeline(faulty.layout, model::QuadrupedKinematics(), FrontendNoise{}, po,
                             context);
    const std::unique_ptr<Estimator> e = makeEstimator(filter_);
    eval::MonitoredRunOptions mo;
    mo.degrade = degrade;
    return eval::runMonitored(*e, faulty, pipeline, eval::initialState(faulty), mo);
  };

  const std::vector<FaultCase> cases = {
      {"none", [](const io::Log& l) { return l; }, false},
      {"IMU rows missing 1.50-1.55 s",
       [](const io::Log& l) { return eval::dropImuRows(l, kOnset, 0.05); }, false},
      {"FR knee encoder frozen from 1.5 s",
       [](const io::Log& l) { return eval::freezeEncoder(l, 5, kOnset); }, true},
      {"FR force sensor +30 N over 1-3 s",
       [](const io::Log& l) { return eval::driftForce(l, 1, 1.0, 2.0, 30.0); }, true},
      {"every force sensor 0 N, 1.5-2.5 s",
       [](const io::Log& l) { return eval::silenceForces(l, kOnset, 1.0); }, true},
      {"accelerometer +10 g z, 1.50-1.51 s",
       [](const io::Log& l) {
         return eval::shockAccelerometer(l, kOnset, 0.01, Eigen::Vector3d(0.0, 0.0, 98.1));
       },
       false},
      {"encoders 20 ms late", [](const io::Log& l) { return eval::delayEncoders(l, 0.02); }, false},
  };
  out << "# " << filter_ << " on a " << kDuration << " s physics trot (seed " << seed_
      << "), contacts from the fallback chain; errors are maxima: position / attitude / "
         "velocity / position sigma, then the estimator's and the pipeline's faults\n\n"
      << "| fault | alarms (first raised) | error with the monitor's answers | without them |\n"
      << "|---|---|---|---|\n";
  for (const FaultCase& c : cases) {
    const io::Log faulty = c.inject(log);
    const eval::MonitoredRun r = monitored(faulty, true);
    const std::string raw = c.has_answer ? errors(monitored(faulty, false)) : "-";
    out << "| " << c.name << " | " << alarms(r) << " | " << errors(r) << " | " << raw << " |\n";
  }
  return 0;
}

}  // namespace legkit::tools
