// Reference solution of exercise 57.7.1.
#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>

#include "ex57_7_1.hpp"

namespace ex57_7_1 {

// d2 = r^T S^-1 r with S = H P H^T + R (the innovation covariance of the foot's velocity): solved
// through S's Cholesky factor, never by inverting S.
double mahalanobisSquared(const FootResidual& foot, const Matrix9& P) {
  const Eigen::Matrix3d S = foot.H * P * foot.H.transpose() + foot.R;
  const Eigen::LLT<Eigen::Matrix3d> llt(S);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("H P H^T + R is not positive definite");
  return foot.r.dot(llt.solve(foot.r));
}

namespace {

// P(chi2_3 <= x) in closed form: erf(sqrt(x / 2)) - sqrt(2 x / pi) exp(-x / 2).
double chiSquare3Cdf(double x) {
  return std::erf(std::sqrt(0.5 * x)) - std::sqrt(2.0 * x / M_PI) * std::exp(-0.5 * x);
}

}  // namespace

// The CDF rises monotonically from 0 at x = 0: bisection between 0 and a bracket doubled until
// the CDF there exceeds alpha.
double chiSquare3Quantile(double alpha) {
  if (!(alpha > 0.0 && alpha < 1.0)) throw std::invalid_argument("alpha must be in (0, 1)");
  double lo = 0.0, hi = 1.0;
  while (chiSquare3Cdf(hi) < alpha) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chiSquare3Cdf(mid) < alpha ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

SlipVerdict detectSlip(const FootResidual* feet, int n, const Matrix9& P, double alpha) {
  if (n < 0 || n > 8) throw std::invalid_argument("between 0 and 8 feet");
  const double threshold = chiSquare3Quantile(alpha);
  SlipVerdict verdict;
  verdict.num_feet = n;
  for (int i = 0; i < n; ++i) {
    const double d2 = mahalanobisSquared(feet[i], P);
    verdict.feet[i] = {feet[i].foot, d2, d2 > threshold};
  }
  return verdict;
}

}  // namespace ex57_7_1
