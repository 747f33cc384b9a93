#include "sim_command.hpp"

#include <chrono>
#include <stdexcept>

#include "io/log_writer.hpp"
#include "model/quadruped.hpp"
#include "output.hpp"
#include "sim/simulator.hpp"

namespace legkit::tools {
namespace {

int legByName(const std::string& name) {
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    if (name == model::legName(leg)) return leg;
  }
  throw UsageError("--slip-foot: unknown leg '" + name + "' (FL, FR, RL or RR)");
}

// "START:DURATION" in seconds.
sim::Dropout parseDropout(const std::string& text) {
  const std::size_t colon = text.find(':');
  try {
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    std::size_t used_start = 0, used_duration = 0;
    const std::string start = text.substr(0, colon), duration = text.substr(colon + 1);
    sim::Dropout d{std::stod(start, &used_start), std::stod(duration, &used_duration)};
    if (used_start != start.size() || used_duration != duration.size() || !(d.duration > 0.0)) {
      throw std::invalid_argument("bad numbers");
    }
    return d;
  } catch (const std::exception&) {
    throw UsageError("--dropout: expected START:DURATION in seconds (e.g. 10:0.05), got '" + text +
                     "'");
  }
}

}  // namespace

SimCommand::SimCommand(CLI::App& app)
    : command_(app.add_subcommand("sim", "Simulate a scenario and write its log (CSV)")) {
  CLI::App& c = *command_;
  std::string names;
  for (const std::string& n : sim::scenarioNames()) names += (names.empty() ? "" : ", ") + n;
  c.add_option("--scenario", scenario_, "Motion: " + names)
      ->check(CLI::IsMember(sim::scenarioNames()))
      ->capture_default_str();
  c.add_option("--duration", duration_, "Simulated time [s]")->capture_default_str();
  c.add_option("--rate", rate_, "IMU and log rate [Hz]")->capture_default_str();
  c.add_option("--seed", seed_, "Random seed (same seed, same log)")->capture_default_str();
  c.add_option("--out", out_, "Log file to write")->capture_default_str();
  c.add_flag("--noiseless", noiseless_, "No IMU or encoder noise, zero biases");
  c.add_flag("--no-ground-truth", no_ground_truth_, "Leave out the gt_ columns");
  c.add_option(
       "--foot-columns", foot_columns_,
       "Describe the legs by body-frame foot columns instead of joint columns: none (joints), "
       "diagonal (feet with variances) or full (feet with covariances)")
      ->check(CLI::IsMember({"none", "diagonal", "full"}))
      ->capture_default_str();
  c.add_option("--slip-foot", slip_foot_, "Fault: this foot (FL, FR, RL, RR) slips in stance");
  c.add_option("--slip-start", slip_start_, "Slip start [s]")->capture_default_str();
  c.add_option("--slip-duration", slip_duration_, "Slip duration [s]")->capture_default_str();
  c.add_option("--slip-speed", slip_speed_, "Slip speed [m/s]")->capture_default_str();
  c.add_option("--slip-direction", slip_direction_, "Slip direction in the world: X Y")
      ->expected(2)
      ->capture_default_str();
  c.add_option("--contact-offset", contact_offset_,
               "Fault: logged contact flags lag the true contacts by this [s]")
      ->capture_default_str();
  c.add_option("--dropout", dropouts_, "Fault: no IMU samples in START:DURATION [s]; repeatable");
  c.add_option("--dropout-probability", dropout_probability_,
               "Fault: each IMU sample is lost with this probability")
      ->capture_default_str();
}

int SimCommand::run(std::ostream& out) const {
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
  const auto seconds = [](auto d) { return std::chrono::duration<double>(d).count(); };
  out << "legkit sim: " << scenario_ << ", " << duration_ << " s, seed " << seed_ << ": "
      << result.log.rows.size() << " rows written to " << out_ << " (simulated in "
      << seconds(simulated - start) << " s, written in " << seconds(written - simulated) << " s)\n";
  return 0;
}

}  // namespace legkit::tools
