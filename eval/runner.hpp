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
};

// Resets the estimator to x0, feeds it every row of the log (through the front end) and records
// its estimate after each row.
RunResult runOnLog(Estimator& estimator, const io::Log& log, const LogFrontend& frontend,
                   const EstimateSample& x0);

// The initial state a run starts from: the log's ground truth at row 0 when it has one,
// otherwise at rest at the origin with roll and pitch from the first accelerometer sample.
EstimateSample initialState(const io::Log& log);

}  // namespace legkit::eval
