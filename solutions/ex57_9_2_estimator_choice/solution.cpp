// Reference solution to exercise 57.9.2.
#include <cmath>
#include <stdexcept>

#include "estimation/estimators.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "ex57_9_2.hpp"
#include "model/quadruped.hpp"

namespace ex57_9_2 {

// Section 57.9's selection guide, with the drift the tests measure (answer.md):
// (a) short patrols on flat ground: the simplest filter that holds a few cm per metre;
// (b) a kilometre of proprioception alone drifts by metres: LiDAR corrections, loosely coupled
//     on an onboard computer with a budget;
// (c) a hand placed to a centimetre cannot live with an unobservable, drifting yaw: tight coupling
//     of vision/LiDAR with the legs and the IMU.
Choice choose(Scenario scenario) {
  switch (scenario) {
    case Scenario::kFactoryPatrol:
      return Choice::kLinearKf;
    case Scenario::kMineExploration:
      return Choice::kModularLidarEkf;
    case Scenario::kHumanoidBuilding:
      return Choice::kFactorGraph;
  }
  throw std::invalid_argument("choose: unknown scenario");
}

Drift drift(const legkit::io::Log& log, const std::string& estimator) {
  if (!log.layout.ground_truth || log.rows.empty())
    throw std::invalid_argument("drift: the log has no ground truth");
  const auto filter = legkit::makeEstimator(estimator);
  const legkit::LogFrontend frontend(log.layout, legkit::model::QuadrupedKinematics());
  const legkit::eval::RunResult run =
      legkit::eval::runOnLog(*filter, log, frontend, legkit::eval::initialState(log));
  if (run.failed())
    throw std::invalid_argument("drift: " + estimator +
                                " failed: " + legkit::eval::describe(*run.failure));
  Drift d;
  for (std::size_t k = 1; k < log.rows.size(); ++k)
    d.distance += (log.rows[k].gt_p - log.rows[k - 1].gt_p).norm();
  const legkit::io::LogRow& last = log.rows.back();
  const legkit::EstimateSample& x = run.trajectory.back();
  d.position_error = (x.p - last.gt_p).norm();
  d.yaw_error_deg =
      std::abs(legkit::eval::yawError(x.q.toRotationMatrix(), last.gt_q.toRotationMatrix())) *
      180.0 / M_PI;
  return d;
}

}  // namespace ex57_9_2
