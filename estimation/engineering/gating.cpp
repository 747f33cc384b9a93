#include "estimation/engineering/gating.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace legkit::engineering {

void checkGatingParams(const GatingParams& params, const char* who) {
  if (!(params.n_sigma > 0.0) || !std::isfinite(params.n_sigma))
    throw std::invalid_argument(std::string(who) + ": gating.n_sigma must be positive and finite");
  if (!(params.max_gated_time >= 0.0) || !std::isfinite(params.max_gated_time))
    throw std::invalid_argument(std::string(who) +
                                ": gating.max_gated_time must be finite and non-negative");
}

double nSigmaProbability(double n_sigma) {
  return std::erf(n_sigma / std::sqrt(2.0));
}

namespace {
constexpr double kGammaThreeHalves = 0.88622692545275801365;  // Gamma(3/2) = sqrt(pi) / 2
}  // namespace

double chiSquareCdf(int dof, double x) {
  if (dof < 1 || dof > 64)
    throw std::invalid_argument("chiSquareCdf: dof must be in 1..64, got " + std::to_string(dof));
  if (!(x > 0.0)) return 0.0;
  if (std::isinf(x)) return 1.0;
  const double y = 0.5 * x;
  // P(a0, y) and its term y^a0 e^-y / Gamma(a0 + 1), a0 = 1/2 (odd dof) or 1 (even dof).
  const bool odd = dof % 2 == 1;
  double a = odd ? 0.5 : 1.0;
  double P = odd ? std::erf(std::sqrt(y)) : -std::expm1(-y);
  double term = odd ? std::sqrt(y) * std::exp(-y) / kGammaThreeHalves : y * std::exp(-y);
  for (; a < 0.5 * dof; a += 1.0) {
    P -= term;              // P(a + 1, y) = P(a, y) - y^a e^-y / Gamma(a + 1)
    term *= y / (a + 1.0);  // y^(a+1) e^-y / Gamma(a + 2)
  }
  return P < 0.0 ? 0.0 : P;
}

double chiSquareQuantile(int dof, double p) {
  if (!(p > 0.0 && p <= 1.0))
    throw std::invalid_argument("chiSquareQuantile: p must be in (0, 1], got " + std::to_string(p));
  chiSquareCdf(dof, 1.0);  // checks dof
  if (p == 1.0) return std::numeric_limits<double>::infinity();
  double lo = 0.0, hi = static_cast<double>(dof) + 10.0;
  while (chiSquareCdf(dof, hi) < p) {
    lo = hi;
    hi *= 2.0;
    if (hi > 1e6) return std::numeric_limits<double>::infinity();  // p beyond double's digits
  }
  while (hi - lo > 1e-12 * hi) {
    const double mid = 0.5 * (lo + hi);
    (chiSquareCdf(dof, mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

FootGate::FootGate(const GatingParams& params, const char* who)
    : params_(params), threshold_(std::numeric_limits<double>::infinity()) {
  checkGatingParams(params, who);
  threshold_ = chiSquareQuantile(3, nSigmaProbability(params.n_sigma));
  reset();
}

FootGate::Decision FootGate::decide(int foot, double d2, double t) {
  if (d2 <= threshold_) {
    clear(foot);
    return Decision::kUse;
  }
  double& since = gated_since_[foot];
  if (std::isnan(since)) since = t;
  if (t - since >= params_.max_gated_time) {
    clear(foot);
    return Decision::kReinitialise;
  }
  return Decision::kGate;
}

}  // namespace legkit::engineering
