#include "study_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>

#include "consistency_report.hpp"
#include "convergence_report.hpp"
#include "estimation/estimators.hpp"
#include "eval/bias_variance.hpp"
#include "eval/metrics.hpp"
#include "eval/monte_carlo.hpp"
#include "eval/runner.hpp"
#include "output.hpp"
#include "shard.hpp"
#include "study_filters.hpp"
#include "study_fusion.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

namespace fs = std::filesystem;

// Progress on standard error: redrawn in place on a terminal, plain lines into a file or pipe.
Progress stderrProgress() {
  return Progress(std::cerr, isatty(fileno(stderr)) != 0);
}

}  // namespace

int StudyCommand::writeShard(std::ostream& out, const std::string& study, const fs::path& dir,
                             const std::function<void(std::ostream&)>& rows,
                             const ShardRun& run) const {
  writeStudyShard(dir, study,
                  {{"runs", run.runs},
                   {"duration", run.duration},
                   {"seed", seed_},
                   {"correct_yaw", correct_yaw_}},
                  run.shard, run.block, rows);
  out << "study " << study << ", shard " << run.shard.text() << ": runs " << run.block.begin << ".."
      << run.block.end - 1 << " of " << run.runs << " (seeds " << seed_ + run.block.begin << ".."
      << seed_ + run.block.end - 1 << ") in " << dir.string()
      << "/; `legkit merge OUT SHARD_DIR...` makes the study's table and files from all "
      << run.shard.count << " shards\n";
  return kExitOk;
}

StudyCommand::StudyCommand(CLI::App& app)
    : command_(app.add_subcommand("study", "Monte Carlo studies behind the chapters' figures")),
      contact_(*command_),
      faults_(*command_) {
  command_->require_subcommand(1);
  addStudyFusion(*command_);  // `study fusion` (57.8): its options live in its subcommand
  consistency_ = command_->add_subcommand(
      "consistency", "ANEES of every filter over runs of the default trot (section 57.5)");
  convergence_ = command_->add_subcommand(
      "convergence", "Initial attitude error 5-90 deg: convergence of LKF, ESKF, InEKF (57.10)");
  sweep_ = command_->add_subcommand(
      "sweep", "Linear KF noise parameters over decades: bias-variance trade-off (ex. 57.4.2)");
  for (CLI::App* c : {consistency_, convergence_, sweep_}) {
    // Unset they stay 0, the study's own; given, each is checked (0, -1 or NaN once fell back to
    // the default silently).
    c->add_option("--runs", runs_, "Monte Carlo runs (per setting); default: the study's own")
        ->check(wholeRange(1, 10000));
    c->add_option("--duration", duration_, "Simulated time per run [s]; default: the study's own")
        ->check(finiteRange(1e-3, kMaxSimulatedSeconds));
    c->add_option("--seed", seed_, "Seed of the first run (run j uses seed + j)")
        ->check(seedNumber())
        ->capture_default_str();
    // -1 once meant every core, silently; more than 256 workers is a typo, not a machine.
    c->add_option("--threads", threads_, "Worker threads (0: every core)")
        ->check(wholeRange(0, 256))
        ->capture_default_str();
    c->add_option("--out", out_dir_,
                  "Output folder (default legkit-out/study-<name>, -shard-<i>-of-<N> for a shard)")
        ->check(nonEmptyName());
    c->add_flag("!--no-plots", plots_, "Do not draw the PNG figure");
  }
  consistency_->add_flag("--correct-yaw", correct_yaw_,
                         "The plain filters: stance feet correct the heading (feet.correct_yaw: "
                         "true); by default the heading rule of 57.5");
  for (CLI::App* c : {consistency_, convergence_, sweep_}) {
    c->add_option("--shard", shard_,
                  "Run shard i of N (a block of the runs) into --out; `legkit merge` combines "
                  "the N shards into exactly the single-machine study")
        ->check(shardSpec())
        ->capture_default_str();
  }
}

int StudyCommand::run(std::ostream& out) const {
  if (contact_.parsed()) return contact_.run(out);
  if (faults_.parsed()) return faults_.run(out);
  if (const CLI::App* fusion = command_->get_subcommand("fusion"); fusion->parsed()) {
    return runStudyFusion(*fusion, out);
  }
  try {
    if (*consistency_) return consistency(out);
    if (*convergence_) return convergence(out);
    return sweep(out);
  } catch (const eval::RunFailedError& e) {  // the input was fine: a filter failed in a run
    std::cerr << "legkit study: " << e.what() << "\n";
    return kExitUnhealthy;
  }
}

int StudyCommand::plot(std::ostream& out, const std::string& study, const std::string& dir) const {
  if (!plots_) return kExitOk;
  const std::string failed = tools::plot("study_plots.py", {study, dir});
  out << (failed.empty() ? "figure: " + dir + "/" + study + ".png" : failed) << '\n';
  return plotFailed(failed) ? kExitInput : kExitOk;
}

// ANEES_k of each filter (with its bounds) over `runs` runs of the default trot, every filter with
// its default parameters; each run's initial error and IMU biases drawn from eval::InitialPrior.
// The default horizon is long (12 runs of 300 s): a filter that slowly grows over-confident
// looks consistent for the first minute (chapter 57.10), so the table also gives the ANEES of
// the last tenth of the run.
int StudyCommand::consistency(std::ostream& out) const {
  const Shard shard = parseShard(shard_);
  const int runs = runs_ > 0 ? runs_ : 12;
  const double duration = duration_ > 0 ? duration_ : 300.0;
  const Block block = shardBlock(shard, runs, "runs");
  const fs::path dir = studyFolder(out_dir_, "consistency", shard);
  makeOutputFolder(dir);  // before the runs: a bad --out fails at once
  eval::MonteCarloOptions options;
  options.runs = block.end - block.begin;
  options.sim.duration = duration;
  // Run j is seeded seed + j, sharded or not.
  options.first_seed = seed_ + static_cast<unsigned>(block.begin);
  options.threads = threads_;
  options.prior = eval::InitialPrior{};
  Progress progress = stderrProgress();
  options.on_progress = [&](int done, int total) { progress.run("consistency", done, total); };
  MonteCarloRows rows{block.begin, filterNames(), {}, {}, {}};
  rows.runs.assign(rows.names.size(), std::vector<eval::RunSummary>(options.runs));
  rows.extra.assign(rows.names.size(), std::vector<std::vector<double>>(options.runs));
  options.on_run = [&rows](int j, std::size_t e, const io::Log&, const eval::RunResult& run) {
    rows.runs[e][j] = {{}, run.nees, run.nees_dof, run.us_per_step};  // each slot written once
  };
  std::vector<eval::NamedEstimator> filters;
  filters.reserve(rows.names.size());
  for (const std::string& name : rows.names) {
    filters.push_back({name, [name, plain = correct_yaw_] {
                         return makeFamilyFilter(name, [plain](invariant::FilterParams& p) {
                           p.feet_correct_yaw = plain;
                         });
                       }});
  }
  const std::vector<eval::MonteCarloEstimate> result = eval::monteCarlo(options, filters);
  progress.clear();
  rows.t = result.front().t;
  for (std::size_t e = 0; e < result.size(); ++e) {
    for (int j = 0; j < options.runs; ++j) {
      rows.runs[e][j].metrics = result[e].runs[j];
      rows.extra[e][j] = {result[e].runs[j].yaw_rmse_deg};  // the report's yaw column
    }
  }
  if (shard.whole()) {
    reportConsistency(out, dir, rows, duration, correct_yaw_);
    return plot(out, "consistency", dir.string());
  }
  return writeShard(out, "consistency", dir, [&](std::ostream& f) { writeMonteCarloRows(f, rows); },
                    {runs, duration, shard, block});
}

// Each filter started with its attitude turned by a given angle about a random axis (the same
// axes for every filter), its initial attitude sigma set to that angle. A run has converged when
// from some time t_c to the end its roll/pitch error stays below 2 degrees and its body-frame
// velocity error below 0.1 m/s, with t_c at least 5 s before the end. Yaw is unobservable and not
// judged; that is also why velocity is compared in the body frame: a heading error that is kept
// rotates the world-frame velocity (0.5 m/s x 15 deg = 0.13 m/s).
int StudyCommand::convergence(std::ostream& out) const {
  const Shard shard = parseShard(shard_);
  std::vector<double> angles;
  for (int a = 5; a <= 90; a += 5) angles.push_back(a);
  const int runs = runs_ > 0 ? runs_ : 10;
  const double duration = duration_ > 0 ? duration_ : 20.0;
  const Block block = shardBlock(shard, runs, "runs");
  constexpr double tilt_limit = 2.0 * M_PI / 180.0, velocity_limit = 0.1, settle = 5.0;

  const fs::path dir = studyFolder(out_dir_, "convergence", shard);
  makeOutputFolder(dir);
  ConvergenceRows rows = convergenceRows(block.begin, block.end - block.begin, angles,
                                         {"linear-kf", "eskf", "invariant-ekf"});
  Progress progress = stderrProgress();
  for (std::size_t a = 0; a < angles.size(); ++a) {
    const double angle = angles[a] * M_PI / 180.0;
    eval::MonteCarloOptions options;
    options.runs = rows.count;
    options.sim.duration = duration;
    options.first_seed = seed_ + static_cast<unsigned>(block.begin);  // run j: seed_ + j
    options.threads = threads_;
    const std::string what = "convergence, " + formatFixed(angles[a], 0) + " deg";
    options.on_progress = [&](int done, int total) { progress.run(what, done, total); };
    const unsigned first = static_cast<unsigned>(block.begin);
    options.initial_state = [angle, first, this](const io::Log& log, int run) {
      std::mt19937 rng(seed_ * 7919u + first + static_cast<unsigned>(run));
      std::normal_distribution<double> n;
      const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
      EstimateSample x0 = eval::initialState(log);
      x0.q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis)) * x0.q;
      return x0;
    };
    // Each run's slot written once, by the thread that ran it.
    options.on_run = [&, a](int j, std::size_t e, const io::Log& log, const eval::RunResult& run) {
      const double t_end = log.rows.back().t;
      double t_c = log.rows.front().t;  // the last time the limits were broken
      for (std::size_t k = 0; k < log.rows.size(); ++k) {
        const io::LogRow& row = log.rows[k];
        const EstimateSample& x = run.trajectory[k];
        const bool ok =
            eval::tiltError(x.q.toRotationMatrix(), row.gt_q.toRotationMatrix()) < tilt_limit &&
            (x.q.conjugate() * x.v - row.gt_q.conjugate() * row.gt_v).norm() < velocity_limit;
        if (!ok) t_c = row.t;
      }
      if (t_c <= t_end - settle) rows.time[a][e][j] = t_c - log.rows.front().t;
    };
    std::vector<eval::NamedEstimator> filters;
    filters.reserve(rows.filters.size());
    for (const std::string& name : rows.filters) {
      filters.push_back(
          {name, [name, angle] { return makeWithInitialAttitudeSigma(name, angle); }});
    }
    eval::monteCarlo(options, filters);
  }
  progress.clear();
  if (shard.whole()) {
    reportConvergence(out, dir, rows, duration);
    return plot(out, "convergence", dir.string());
  }
  return writeShard(out, "convergence", dir,
                    [&](std::ostream& f) { writeConvergenceRows(f, rows); },
                    {runs, duration, shard, block});
}

// The linear KF with one noise variance at a time scaled from 1e-3 to 1e3 times its nominal
// value: mean position RMSE, the velocity error split into bias and variance
// (eval/bias_variance.hpp, 1 s window), and ANEES/dof over the runs.
int StudyCommand::sweep(std::ostream& out) const {
  const Shard shard = parseShard(shard_);
  const int runs = runs_ > 0 ? runs_ : 10;
  const double duration = duration_ > 0 ? duration_ : 20.0;
  const Block block = shardBlock(shard, runs, "runs");
  constexpr double window = kSweepWindow;
  const fs::path dir = studyFolder(out_dir_, "sweep", shard);
  makeOutputFolder(dir);
  const int count = block.end - block.begin;
  MonteCarloRows rows{block.begin, {}, {}, {}, {}};
  Progress progress = stderrProgress();
  for (int p = 0; p < 3; ++p) {
    for (int i = 0; i < kSweepScales; ++i) {
      const double scale = sweepScale(i);
      LinearKfScales scales;
      (p == 0   ? scales.foot_process_noise
       : p == 1 ? scales.accel_noise
                : scales.measurement_noise) = scale;
      eval::MonteCarloOptions options;
      options.runs = count;
      options.sim.duration = duration;
      options.first_seed = seed_ + static_cast<unsigned>(block.begin);  // run j: seed_ + j
      options.threads = threads_;
      options.frontend_noise = scaledFrontendNoise(eval::matchedFrontendNoise(options.sim), scales);
      const std::string what = "sweep, " + sweepSetting(p, i);
      options.on_progress = [&](int done, int total) { progress.run(what, done, total); };
      std::vector<eval::RunSummary> summaries(count);
      std::vector<std::vector<double>> extra(count);
      // Each run's slot written once, by the thread that ran it; summed in run order after.
      options.on_run = [&](int j, std::size_t, const io::Log& log, const eval::RunResult& run) {
        const eval::BiasVariance bv = eval::velocityBiasVariance(log, run.trajectory, window);
        summaries[j] = {{}, run.nees, run.nees_dof, run.us_per_step};
        extra[j] = {bv.bias, bv.variance};
      };
      const auto r =
          eval::monteCarlo(options, {{"linear-kf", [scales] { return makeLinearKf(scales); }}});
      for (int j = 0; j < count; ++j) summaries[j].metrics = r[0].runs[j];
      rows.names.push_back(sweepSetting(p, i));
      rows.t = r[0].t;
      rows.runs.push_back(std::move(summaries));
      rows.extra.push_back(std::move(extra));
    }
  }
  progress.clear();
  if (shard.whole()) {
    reportSweep(out, dir, rows, duration);
    return plot(out, "sweep", dir.string());
  }
  return writeShard(out, "sweep", dir, [&](std::ostream& f) { writeMonteCarloRows(f, rows); },
                    {runs, duration, shard, block});
}

}  // namespace legkit::tools
