#include "sim_command.hpp"

#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "closed_loop.hpp"
#include "estimation/estimators.hpp"
#include "io/log_writer.hpp"
#include "model/quadruped.hpp"
#include "output.hpp"
#include "scenarios.hpp"
#include "sim/physics_simulator.hpp"
#include "sim/simulator.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

int legByName(const std::string& name) {
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    if (name == model::legName(leg)) return leg;
  }
  throw UsageError("--slip-foot: unknown leg '" + name + "' (FL, FR, RL or RR)");
}

// "START:DURATION" in seconds: a start in [0, 3600] s and a duration in (0, 3600] s, both
// finite (an hour, the longest simulated run: kMaxSimulatedSeconds).
sim::Dropout parseDropout(const std::string& text) {
  const std::size_t colon = text.find(':');
  try {
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    std::size_t used_start = 0, used_duration = 0;
    const std::string start = text.substr(0, colon), duration = text.substr(colon + 1);
    sim::Dropout d{std::stod(start, &used_start), std::stod(duration, &used_duration)};
    if (used_start != start.size() || used_duration != duration.size() ||
        !(d.start >= 0.0 && d.start <= kMaxSimulatedSeconds) ||
        !(d.duration > 0.0 && d.duration <= kMaxSimulatedSeconds)) {
      throw std::invalid_argument("bad numbers");
    }
    return d;
  } catch (const std::exception&) {
    throw UsageError(
        "--dropout: expected START:DURATION in seconds, START in [0, 3600], DURATION in (0, "
        "3600] (e.g. 10:0.05), got " +
        detail::shown(text));
  }
}

// A value of `option` inside [low, high], or a UsageError naming the option and the range.
void checkRange(const char* option, double value, double low, double high, const char* unit) {
  if (!(value >= low && value <= high)) {
    std::ostringstream os;
    os << option << ": " << value << " is out of range [" << low << ", " << high << "]" << unit;
    throw UsageError(os.str());
  }
}

double seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

}  // namespace

SimCommand::SimCommand(CLI::App& app)
    : command_(app.add_subcommand("sim", "Simulate a scenario and write its log (CSV)")) {
  CLI::App& c = *command_;
  c.add_option("--scenario", scenario_, "Motion, " + scenarioHelp())
      ->check(CLI::IsMember(allScenarioNames()))
      ->capture_default_str();
  duration_option_ = c.add_option("--duration", duration_,
                                  "Simulated time [s], up to 3600 (default 60; a physics "
                                  "scenario's own length, e.g. 10 s for physics-stand)")
                         ->check(finiteRange(1e-3, kMaxSimulatedSeconds));
  // An IMU samples at 100 Hz to a few kHz: below 10 Hz a 2 Hz gait is not sampled, above 10 kHz
  // no IMU reads; the physics scenarios also keep to [100 Hz, their physics rate]. Times the
  // duration at most kMaxSimulatedSamples (run()).
  c.add_option("--rate", rate_, "IMU and log rate [Hz], 10..10000")
      ->check(finiteRange(10.0, 1e4))
      ->capture_default_str();
  c.add_option("--seed", seed_, "Random seed (same seed, same log)")
      ->check(seedNumber())
      ->capture_default_str();
  c.add_option("--out", out_, "Log file to write")->check(nonEmptyName())->capture_default_str();
  c.add_flag("--noiseless", noiseless_, "No IMU or encoder noise, zero biases");
  c.add_flag("--no-ground-truth", no_ground_truth_, "Leave out the gt_ columns");
  c.add_option(
       "--foot-columns", foot_columns_,
       "Describe the legs by body-frame foot columns instead of joint columns: none (joints), "
       "diagonal (feet with variances) or full (feet with covariances)")
      ->check(CLI::IsMember({"none", "diagonal", "full"}))
      ->capture_default_str();
  // The slip: within the longest run; a foot sliding faster than 10 m/s is not slipping, it is
  // thrown; the direction is normalised (its scale does not matter, the cap keeps its norm
  // finite). Each of them only with --slip-foot (they were once ignored without it).
  slip_options_ = {c.add_option("--slip-start", slip_start_, "Slip start [s]")
                       ->check(finiteRange(0.0, kMaxSimulatedSeconds))
                       ->capture_default_str(),
                   c.add_option("--slip-duration", slip_duration_, "Slip duration [s]")
                       ->check(finiteRange(1e-3, kMaxSimulatedSeconds))
                       ->capture_default_str(),
                   c.add_option("--slip-speed", slip_speed_, "Slip speed [m/s], 0..10")
                       ->check(finiteRange(0.0, 10.0))
                       ->capture_default_str(),
                   c.add_option("--slip-direction", slip_direction_,
                                "Slip direction in the world: X Y (normalised; not 0 0)")
                       ->expected(2)
                       ->check(finiteRange(-1e3, 1e3))
                       ->capture_default_str()};
  analytic_only_ = {
      c.add_option("--slip-foot", slip_foot_,
                   "Fault (analytic scenarios): this foot (FL, FR, RL, RR) slips in stance")
          ->check(nonEmptyName()),
      // A lag of a second is two whole trot cycles: beyond it the flags describe another step.
      c.add_option("--contact-offset", contact_offset_,
                   "Fault (analytic): logged contact flags lag the true contacts by this [s], "
                   "-1..1")
          ->check(finiteRange(-1.0, 1.0))
          ->capture_default_str(),
      c.add_option("--dropout", dropouts_,
                   "Fault (analytic): no IMU samples in START:DURATION [s]; repeatable"),
      // Below 1: some samples must be left (the simulator refuses a log without any).
      c.add_option("--dropout-probability", dropout_probability_,
                   "Fault (analytic): each IMU sample is lost with this probability, 0..0.99")
          ->check(finiteRange(0.0, 0.99))
          ->capture_default_str()};
  analytic_only_.insert(analytic_only_.end(), slip_options_.begin(), slip_options_.end());
  analytic_only_.push_back(c.get_option("--foot-columns"));
  friction_option_ = c.add_option("--friction", friction_,
                                  "Physics: friction coefficient of the ground, 0.01..2 (patches "
                                  "such as the ice keep their own)")
                         ->check(finiteRange(0.01, 2.0))
                         ->capture_default_str();
  push_option_ = c.add_option("--push", push_,
                              "Physics: lateral push on the standing trunk [N], 0..300 (the push "
                              "scenarios: physics-push, physics-ice-push)")
                     ->check(finiteRange(0.0, 300.0));
  std::vector<std::string> estimators = estimatorNames();
  std::string estimator_list;
  for (const std::string& n : estimators)
    estimator_list += (estimator_list.empty() ? "" : ", ") + n;
  closed_loop_option_ = c.add_option("--closed-loop", closed_loop_,
                                     "Physics: the controller acts on this estimator's estimate "
                                     "instead of the truth: " +
                                         estimator_list)
                            ->check(CLI::IsMember(estimators));
}

int SimCommand::run(std::ostream& out) const {
  return isPhysicsScenario(scenario_) ? runPhysics(out) : runAnalytic(out);
}

int SimCommand::runAnalytic(std::ostream& out) const {
  for (const CLI::Option* o : {friction_option_, push_option_, closed_loop_option_}) {
    if (o->count() > 0) {
      throw UsageError(o->get_name() + ": only for the physics scenarios (" + scenarioHelp() + ")");
    }
  }
  if (duration_ * rate_ > kMaxSimulatedSamples) {
    std::ostringstream os;
    os << "--duration " << duration_ << " s at --rate " << rate_ << " Hz: " << duration_ * rate_
       << " samples, at most " << kMaxSimulatedSamples << " (an hour at 1 kHz; about 2 kB each)";
    throw UsageError(os.str());
  }
  for (const CLI::Option* o : slip_options_) {
    if (o->count() > 0 && slip_foot_.empty()) {
      throw UsageError(o->get_name() + ": only with --slip-foot (the foot that slips)");
    }
  }
  if (!slip_foot_.empty() && slip_direction_[0] == 0.0 && slip_direction_[1] == 0.0) {
    throw UsageError("--slip-direction: 0 0 has no direction");
  }
  sim::SimOptions options;
  options.scenario = sim::scenarioByName(scenario_);
  options.duration = duration_;
  options.rate = rate_;
  options.seed = seed_;
  if (noiseless_) options.noiseless();
  options.ground_truth = !no_ground_truth_;
  options.foot_columns = foot_columns_ == "full"       ? io::FootCovariance::kFull
                         : foot_columns_ == "diagonal" ? io::FootCovariance::kDiagonal
                                                       : io::FootCovariance::kNone;
  if (!slip_foot_.empty()) {
    options.faults.slip.leg = legByName(slip_foot_);
    options.faults.slip.start = slip_start_;
    options.faults.slip.duration = slip_duration_;
    options.faults.slip.speed = slip_speed_;
    options.faults.slip.direction = {slip_direction_[0], slip_direction_[1], 0.0};
  }
  options.faults.contact_offset = contact_offset_;
  for (const std::string& d : dropouts_) options.faults.dropouts.push_back(parseDropout(d));
  options.faults.dropout_probability = dropout_probability_;

  const auto start = std::chrono::steady_clock::now();
  const sim::SimResult result = sim::simulate(options);
  const auto simulated = std::chrono::steady_clock::now();
  writeAtomically(out_, [&](std::ostream& f) { io::writeLog(f, result.log, out_); });
  const auto written = std::chrono::steady_clock::now();
  out << "legkit sim: " << scenario_ << ", " << duration_ << " s, seed " << seed_ << ": "
      << result.log.rows.size() << " rows written to " << out_ << " (simulated in "
      << seconds(simulated - start) << " s, written in " << seconds(written - simulated) << " s)\n";
  return 0;
}

int SimCommand::runPhysics(std::ostream& out) const {
  for (const CLI::Option* o : analytic_only_) {
    if (o->count() > 0) {
      throw UsageError(o->get_name() + ": only for the analytic scenarios, not " + scenario_);
    }
  }
  sim::PhysicsOptions options;
  options.scenario = sim::physicsScenarioByName(scenario_);
  options.duration = duration_option_->count() > 0 ? duration_ : options.scenario.duration;
  // --friction and --push are in range (their validators): only where they apply is left.
  if (friction_option_->count() > 0) options.scenario.terrain.friction = friction_;
  if (push_option_->count() > 0) {
    if (options.scenario.pushes.empty()) {
      throw UsageError("--push: " + scenario_ +
                       " has no push (the push scenarios: physics-push, physics-ice-push)");
    }
    for (sim::Push& p : options.scenario.pushes) {  // the same direction, this force
      const double norm = p.force.norm();
      p.force =
          norm > 0.0 ? Eigen::Vector3d(p.force * (push_ / norm)) : Eigen::Vector3d(0.0, push_, 0.0);
    }
  }
  checkPushesInRun(options);
  checkRange("--rate", rate_, 100.0, options.physics_rate, " Hz (at most the physics rate)");
  options.rate = rate_;
  options.seed = seed_;
  if (noiseless_) options.noiseless();
  options.ground_truth = !no_ground_truth_;
  std::unique_ptr<EstimatorBaseState> closed_loop;
  if (!closed_loop_.empty()) {
    closed_loop = std::make_unique<EstimatorBaseState>(
        closed_loop_, physicsLogLayout(options.ground_truth), matchedFrontendNoise(options));
    options.closed_loop = closed_loop.get();
  }

  const auto start = std::chrono::steady_clock::now();
  const sim::PhysicsResult result = sim::simulatePhysics(options);
  const auto simulated = std::chrono::steady_clock::now();
  const std::size_t rows = result.log.rows.size();
  if (rows > 0) {
    writeAtomically(out_, [&](std::ostream& f) { io::writeLog(f, result.log, out_); });
  }
  const auto written = std::chrono::steady_clock::now();
  const std::string loop = closed_loop_.empty() ? "" : ", closed loop on " + closed_loop_;
  if (result.status.fell) {
    std::cerr << "legkit sim: " << scenario_ << loop << ": " << describeFall(result.status) << "; "
              << (rows > 0
                      ? "wrote the log up to then, " + std::to_string(rows) + " rows, to " + out_
                      : "nothing written")
              << '\n';
    return kExitUnhealthy;
  }
  out << "legkit sim: " << scenario_ << " (physics" << loop << "), " << options.duration
      << " s, seed " << seed_ << ": " << rows << " rows written to " << out_ << " (simulated in "
      << seconds(simulated - start) << " s, written in " << seconds(written - simulated) << " s)\n";
  return 0;
}

}  // namespace legkit::tools
