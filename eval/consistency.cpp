#include "eval/consistency.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <lie/so3.hpp>
#include <sstream>
#include <stdexcept>

namespace legkit::eval {

Eigen::Matrix<double, 9, 1> baseError(const EstimateSample& truth, const EstimateSample& estimate) {
  const lie::SO3d R = lie::SO3d::fromQuaternion(truth.q);
  const lie::SO3d R_hat = lie::SO3d::fromQuaternion(estimate.q);
  Eigen::Matrix<double, 9, 1> e;
  e << (R * R_hat.inverse()).Log(), truth.v - estimate.v, truth.p - estimate.p;  // R = Exp(dθ) R̂
  return e;
}

int neesDof(const BaseCovariance& cov) {
  return cov.has_attitude ? 9 : 6;
}

double nees(const EstimateSample& truth, const EstimateSample& estimate,
            const BaseCovariance& cov) {
  const Eigen::Matrix<double, 9, 1> e = baseError(truth, estimate);
  const int first = cov.has_attitude ? 0 : 3;
  const int n = 9 - first;
  const Eigen::MatrixXd P = cov.P.bottomRightCorner(n, n);
  const Eigen::LLT<Eigen::MatrixXd> llt(P);
  if (llt.info() != Eigen::Success || !P.isApprox(P.transpose(), 1e-9) || !P.allFinite()) {
    std::ostringstream os;
    os << "eval::nees: the covariance at t = " << estimate.t
       << " is not symmetric positive definite";
    throw std::invalid_argument(os.str());
  }
  return e.tail(n).dot(llt.solve(e.tail(n)));
}

namespace {

// Regularised lower incomplete gamma P(a, x): its power series for x < a + 1, otherwise one minus
// the continued fraction of the upper function Q(a, x) (modified Lentz).
double lowerGammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefactor = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 1000 && std::abs(term) > 1e-16 * std::abs(sum); ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return sum * std::exp(log_prefactor);
  }
  constexpr double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int n = 1; n < 1000; ++n) {
    const double an = -n * (n - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefactor) * h;
}

}  // namespace

double chiSquareQuantile(double p, double k) {
  if (!(k > 0.0) || !(p > 0.0 && p < 1.0)) {
    std::ostringstream os;
    os << "chiSquareQuantile: need k > 0 and 0 < p < 1, got k = " << k << ", p = " << p;
    throw std::invalid_argument(os.str());
  }
  double lo = 0.0, hi = k + 20.0 * std::sqrt(2.0 * k) + 100.0;  // the CDF at hi is 1 - tiny
  for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (lowerGammaP(0.5 * k, 0.5 * mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

ChiSquareBounds aneesBounds(int dof, int runs, double confidence) {
  if (dof <= 0 || runs <= 0 || !(confidence > 0.0 && confidence < 1.0)) {
    std::ostringstream os;
    os << "aneesBounds: need dof > 0, runs > 0 and 0 < confidence < 1, got " << dof << ", " << runs
       << ", " << confidence;
    throw std::invalid_argument(os.str());
  }
  const double k = static_cast<double>(dof) * runs;
  return {chiSquareQuantile(0.5 * (1.0 - confidence), k) / runs,
          chiSquareQuantile(0.5 * (1.0 + confidence), k) / runs};
}

}  // namespace legkit::eval
