#include "eval/runner.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "eval/consistency.hpp"

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
    const std::optional<BaseCovariance> cov = estimator.covariance();
    if (!cov) continue;
    result.sigma.push_back(cov->P.diagonal().cwiseSqrt());
    result.nees_dof = neesDof(*cov);
    if (log.layout.ground_truth) {
      const io::LogRow& row = log.rows[k];
      const EstimateSample truth{row.t, row.gt_q, row.gt_v, row.gt_p};
      result.nees.push_back(nees(truth, result.trajectory.back(), *cov));
    }
  }
  result.us_per_step = log.rows.empty() ? 0.0 : busy.count() / log.rows.size();
  return result;
}

double normalisedAnees(const RunResult& run) {
  if (run.nees.empty() || run.nees_dof == 0) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (const double e : run.nees) sum += e;
  return sum / static_cast<double>(run.nees.size()) / run.nees_dof;
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
