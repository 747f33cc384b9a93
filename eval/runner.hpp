// Runs an estimator over a whole log and times each step.
#pragma once

#include "estimation/estimator.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/trajectory.hpp"
#include "io/log.hpp"

namespace legkit::eval {

struct RunResult {
  std::string name;
  Trajectory trajectory;   // one estimate per log row
  double us_per_step = 0;  // mean wall time of Estimator::step [microseconds]
  // For filters (Estimator::covariance()), else empty:
  std::vector<Eigen::Matrix<double, 9, 1>> sigma;  // per row, sqrt of diag P: (theta, v, p)
  std::vector<double> nees;  // per row, against the log's ground truth (empty without one)
  int nees_dof = 0;          // 9, or 6 for a filter without attitude; 0 for no covariance
};

// Mean NEES over the rows of one run divided by its degrees of freedom (1 for a consistent
// filter); NaN when the run has no NEES.
double normalisedAnees(const RunResult& run);

// Resets the estimator to x0, feeds it every row of the log (through the front end) and records
// its estimate after each row, and, for a filter, its standard deviations and (when the log has
// ground truth) its NEES.
RunResult runOnLog(Estimator& estimator, const io::Log& log, const LogFrontend& frontend,
                   const EstimateSample& x0);

// The initial state a run starts from: the log's ground truth at row 0 when it has one,
// otherwise at rest at the origin with roll and pitch from the first accelerometer sample.
EstimateSample initialState(const io::Log& log);

}  // namespace legkit::eval
