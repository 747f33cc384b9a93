// Monte Carlo evaluation: the same estimators on many simulated runs that differ only in their
// random seed (sensor noise, bias walks), in parallel on every core.
//
// Per estimator it gathers the accuracy of every run and the consistency over all runs:
//   ANEES_k = (1/M) sum_j NEES_k^(j)   at each row k, against eval::aneesBounds(dof, M)
//   anees   = mean over k of ANEES_k / dof     (1 for a consistent filter)
//   inside  = fraction of rows whose ANEES_k lies inside the 95 % bounds
// Runs are independent, so the result does not depend on the number of threads.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "estimation/estimator.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/consistency.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "sim/simulator.hpp"

namespace legkit::eval {

// An estimator failed in one run (eval::runOnLog set RunResult::failure): the study's averages
// cannot be formed. The message names the estimator, the run, its seed and the failure.
class RunFailedError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct NamedEstimator {
  std::string name;
  std::function<std::unique_ptr<Estimator>()> make;  // a fresh estimator for each run
};

// Per-axis standard deviations of the initial estimate's error and of the true IMU biases at
// t = 0. A NEES study draws both from the prior the filters are given (their defaults are these
// values), so that the covariance each filter claims is right at t = 0 and NEES measures how well
// it stays right. The error is drawn in the kit's convention (estimator.hpp).
struct InitialPrior {
  double attitude = 0.01;    // [rad]
  double velocity = 0.05;    // [m/s]
  double position = 0.01;    // [m]
  double gyro_bias = 0.002;  // [rad/s]
  double accel_bias = 0.02;  // [m/s^2]
};

struct MonteCarloOptions {
  sim::SimOptions sim;  // scenario, duration, noise; its seed is replaced per run
  // The noise the filters are told the contacts have; by default the simulator's own
  // (matchedFrontendNoise), so that NEES tests the filters and not a mismatched noise model.
  std::optional<FrontendNoise> frontend_noise;
  int runs = 20;            // M
  unsigned first_seed = 1;  // run j uses seed first_seed + j
  int threads = 0;          // 0: every hardware thread
  // Called after each run finishes (whether it succeeded or not) with the number of runs done
  // so far and M, never from two threads at once, with done rising from 1 to M: for a study's
  // progress line (tools/legkit/output.hpp).
  std::function<void(int done, int total)> on_progress;
  // The initial state of run j from its log (default: the log's ground truth at row 0). The
  // convergence study uses it to start the filters away from the truth.
  std::function<EstimateSample(const io::Log&, int run)> initial_state;
  // When set, each run's true initial biases and the error of its initial state (applied on top
  // of initial_state) are drawn from this prior, from a stream of the run's seed.
  std::optional<InitialPrior> prior;
  // Called once per run and estimator, from the worker thread, with the full result of that run
  // (trajectory, sigma, NEES) before it is reduced: for studies that need more than the metrics.
  // It must be safe to call from several threads at once.
  std::function<void(int run, std::size_t estimator, const io::Log&, const RunResult&)> on_run;
};

struct MonteCarloEstimate {
  std::string name;
  std::vector<Metrics> runs;  // accuracy of each run, in run order
  std::vector<double> anees;  // ANEES_k at each row (empty for an estimator without covariance)
  std::vector<double> t;      // the time of each row [s]
  int dof = 0;                // 9, 6, or 0 without covariance
  ChiSquareBounds bounds;     // 95 % bounds of each ANEES_k
  double mean_anees = 0.0;    // mean over rows of ANEES_k / dof (NaN without covariance)
  double fraction_inside = 0.0;
  double us_per_step = 0.0;  // mean over runs
};

// The contact noise a simulated log really has: the simulator's encoder noise, and its
// kinematic-model error (SimOptions::foot_position_sigma) as the contact point's uncertainty.
FrontendNoise matchedFrontendNoise(const sim::SimOptions& sim);

// What the reduction below needs of one run of one estimator.
struct RunSummary {
  Metrics metrics;
  std::vector<double> nees;  // NEES_k at each row (empty without covariance)
  int nees_dof = 0;
  double us_per_step = 0.0;
};

// The reduction of monteCarlo: one estimator's runs j = 0..M-1, in run order, into its estimate
// (ANEES_k, bounds, inside, mean). monteCarlo and `legkit merge` (which recomputes a sharded
// study from its shards' per-run rows) share it, so that the two give the same bits. Throws
// std::invalid_argument without runs or when the runs' NEES lengths differ.
MonteCarloEstimate reduceRuns(const std::string& name, const std::vector<double>& t,
                              const std::vector<RunSummary>& runs);

// Throws std::invalid_argument for runs < 1, RunFailedError when an estimator fails in a run;
// rethrows the first error of any run.
std::vector<MonteCarloEstimate> monteCarlo(const MonteCarloOptions& options,
                                           const std::vector<NamedEstimator>& estimators);

}  // namespace legkit::eval
