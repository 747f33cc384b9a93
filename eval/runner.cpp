#include "eval/runner.hpp"

#include <chrono>
#include <stdexcept>

namespace legkit::eval {

RunResult runOnLog(Estimator& estimator, const io::Log& log, const LogFrontend& frontend,
                   const EstimateSample& x0) {
  RunResult result;
  result.name = estimator.name();
  result.trajectory.reserve(log.rows.size());
  estimator.reset(x0);
  std::chrono::duration<double, std::micro> busy{0};
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const double dt = k == 0 ? 0.0 : log.rows[k].t - log.rows[k - 1].t;
    const StepInput in = frontend.input(log.rows[k], dt);
    const auto t0 = std::chrono::steady_clock::now();
    estimator.step(in);
    busy += std::chrono::steady_clock::now() - t0;
    result.trajectory.push_back(estimator.estimate());
  }
  result.us_per_step = log.rows.empty() ? 0.0 : busy.count() / log.rows.size();
  return result;
}

EstimateSample initialState(const io::Log& log) {
  if (log.rows.empty()) throw std::invalid_argument("initialState: the log has no rows");
  const io::LogRow& first = log.rows.front();
  EstimateSample x0;
  x0.t = first.t;
  if (log.layout.ground_truth) {
    x0.q = first.gt_q;
    x0.v = first.gt_v;
    x0.p = first.gt_p;
  } else {
    // At rest the accelerometer reads -R^T g: its direction is world up seen from the body.
    x0.q = Eigen::Quaterniond::FromTwoVectors(first.acc.normalized(), Eigen::Vector3d::UnitZ());
  }
  return x0;
}

}  // namespace legkit::eval
