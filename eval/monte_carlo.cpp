#include "eval/monte_carlo.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>

#include "estimation/log_frontend.hpp"
#include "eval/runner.hpp"
#include "lie/so3.hpp"

namespace legkit::eval {

namespace {

Eigen::Vector3d normal3(std::mt19937& rng, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  return {n(rng), n(rng), n(rng)};
}

}  // namespace

FrontendNoise matchedFrontendNoise(const sim::SimOptions& sim) {
  return {sim.encoder_angle_sigma, sim.foot_position_sigma};
}

MonteCarloEstimate reduceRuns(const std::string& name, const std::vector<double>& t,
                              const std::vector<RunSummary>& runs) {
  if (runs.empty()) throw std::invalid_argument("reduceRuns: " + name + " has no runs");
  const int M = static_cast<int>(runs.size());
  MonteCarloEstimate r;
  r.name = name;
  r.t = t;
  r.dof = runs[0].nees_dof;
  for (const RunSummary& run : runs) {
    r.runs.push_back(run.metrics);
    r.us_per_step += run.us_per_step / M;
  }
  if (r.dof == 0 || runs[0].nees.empty()) {
    r.mean_anees = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  r.bounds = aneesBounds(r.dof, M);
  r.anees.assign(runs[0].nees.size(), 0.0);
  for (const RunSummary& run : runs) {
    if (run.nees.size() != r.anees.size()) {
      throw std::invalid_argument("reduceRuns: " + name + "'s runs have NEES of different lengths");
    }
    for (std::size_t k = 0; k < r.anees.size(); ++k) r.anees[k] += run.nees[k] / M;
  }
  int inside = 0;
  double sum = 0.0;
  for (const double a : r.anees) {
    sum += a;
    inside += a >= r.bounds.lower && a <= r.bounds.upper;
  }
  r.mean_anees = sum / static_cast<double>(r.anees.size()) / r.dof;
  r.fraction_inside = static_cast<double>(inside) / static_cast<double>(r.anees.size());
  return r;
}

std::vector<MonteCarloEstimate> monteCarlo(const MonteCarloOptions& options,
                                           const std::vector<NamedEstimator>& estimators) {
  if (options.runs < 1) throw std::invalid_argument("monteCarlo: runs must be at least 1");
  const int M = options.runs;
  const std::size_t E = estimators.size();
  // results[j][e]: run j of estimator e. Each run writes only its own slot.
  std::vector<std::vector<RunResult>> results(M, std::vector<RunResult>(E));
  std::vector<std::vector<Metrics>> metrics(M, std::vector<Metrics>(E));
  std::vector<double> times;

  std::atomic<int> next{0};
  std::mutex mutex;  // guards first_error, times and done
  int done = 0;      // runs finished, for on_progress
  std::exception_ptr first_error;
  const FrontendNoise noise = options.frontend_noise.value_or(matchedFrontendNoise(options.sim));
  auto worker = [&] {
    for (int j = next++; j < M; j = next++) {
      try {
        sim::SimOptions sim = options.sim;
        sim.seed = options.first_seed + static_cast<unsigned>(j);
        std::mt19937 rng(sim.seed * 2654435761u + 17u);  // apart from the simulator's streams
        if (options.prior) {
          sim.initial_bias.b_g = normal3(rng, options.prior->gyro_bias);
          sim.initial_bias.b_a = normal3(rng, options.prior->accel_bias);
        }
        const io::Log log = sim::simulate(sim).log;
        const LogFrontend frontend(log.layout, model::QuadrupedKinematics(), noise);
        EstimateSample x0 =
            options.initial_state ? options.initial_state(log, j) : initialState(log);
        if (options.prior) {  // truth = x0 (+) e, so x0 = truth (-) e
          const Eigen::Matrix3d dR =
              lie::SO3d::Exp(-normal3(rng, options.prior->attitude)).matrix();
          x0.q = Eigen::Quaterniond(dR * x0.q.toRotationMatrix());
          x0.v -= normal3(rng, options.prior->velocity);
          x0.p -= normal3(rng, options.prior->position);
        }
        for (std::size_t e = 0; e < E; ++e) {
          const std::unique_ptr<Estimator> estimator = estimators[e].make();
          RunResult run = runOnLog(*estimator, log, frontend, x0);
          if (run.failed()) {
            throw RunFailedError(estimators[e].name + " failed in run " + std::to_string(j) +
                                 " (seed " + std::to_string(sim.seed) +
                                 "): " + describe(*run.failure));
          }
          metrics[j][e] = compare(log, run.trajectory);
          if (options.on_run) options.on_run(j, e, log, run);
          run.trajectory.clear();  // the metrics hold what is needed; keep memory bounded
          run.sigma.clear();
          results[j][e] = std::move(run);
        }
        const std::lock_guard<std::mutex> lock(mutex);
        if (times.empty()) {
          for (const io::LogRow& row : log.rows) times.push_back(row.t);
        }
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!first_error) first_error = std::current_exception();
      }
      if (options.on_progress) {
        const std::lock_guard<std::mutex> lock(mutex);  // done counted under the lock: 1, 2, .. M
        options.on_progress(++done, M);
      }
    }
  };
  const int threads = std::min(
      M, options.threads > 0 ? options.threads
                             : std::max(1, static_cast<int>(std::thread::hardware_concurrency())));
  std::vector<std::thread> pool;
  for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
  if (first_error) std::rethrow_exception(first_error);

  std::vector<MonteCarloEstimate> out;
  out.reserve(E);
  for (std::size_t e = 0; e < E; ++e) {
    std::vector<RunSummary> runs(M);
    for (int j = 0; j < M; ++j) {
      runs[j] = {metrics[j][e], std::move(results[j][e].nees), results[j][e].nees_dof,
                 results[j][e].us_per_step};
    }
    out.push_back(reduceRuns(estimators[e].name, times, runs));
  }
  return out;
}

}  // namespace legkit::eval
