#include "eval/bias_variance.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace legkit::eval {

BiasVariance velocityBiasVariance(const io::Log& truth, const Trajectory& estimate, double window) {
  if (!truth.layout.ground_truth) {
    throw std::invalid_argument("velocityBiasVariance: the log has no ground truth");
  }
  if (truth.rows.size() != estimate.size() || estimate.empty()) {
    throw std::invalid_argument("velocityBiasVariance: " + std::to_string(estimate.size()) +
                                " estimates for " + std::to_string(truth.rows.size()) +
                                " log rows");
  }
  if (!(window > 0.0)) {
    throw std::invalid_argument("velocityBiasVariance: window must be > 0 s, got " +
                                std::to_string(window));
  }
  const std::size_t n = estimate.size();
  // Prefix sums of e_k make every moving average O(1).
  std::vector<Eigen::Vector3d> sum(n + 1, Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < n; ++k) sum[k + 1] = sum[k] + (estimate[k].v - truth.rows[k].gt_v);

  BiasVariance out;
  std::size_t lo = 0, hi = 0;  // the rows [lo, hi) within window / 2 of row k
  for (std::size_t k = 0; k < n; ++k) {
    const double t = truth.rows[k].t;
    while (truth.rows[lo].t < t - 0.5 * window) ++lo;
    while (hi < n && truth.rows[hi].t <= t + 0.5 * window) ++hi;
    const Eigen::Vector3d slow = (sum[hi] - sum[lo]) / static_cast<double>(hi - lo);
    const Eigen::Vector3d fast = (estimate[k].v - truth.rows[k].gt_v) - slow;
    out.bias += slow.squaredNorm();
    out.variance += fast.squaredNorm();
  }
  out.bias = std::sqrt(out.bias / n);
  out.variance /= n;
  return out;
}

}  // namespace legkit::eval
