// Reference solution to exercise 57.2.3.
#include <Eigen/Geometry>
#include <cmath>

#include "ex57_2_3.hpp"

namespace ex57_2_3 {

namespace {

Eigen::Quaterniond expQ(const Eigen::Vector3d& phi) {
  const double t = phi.norm();
  if (t < 1e-12)
    return Eigen::Quaterniond(1.0, 0.5 * phi(0), 0.5 * phi(1), 0.5 * phi(2)).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(t, phi / t));
}

}  // namespace

// Reference: many substeps, each holding the substep's midpoint rate (second order), with
// quaternions; the step under test holds w(0).
double oneStepError(const Rate& w, double dt) {
  const int n = 4000;
  const double h = dt / n;
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  for (int i = 0; i < n; ++i) q = q * expQ(w((i + 0.5) * h) * h);
  const Eigen::Quaterniond q_step = expQ(w(0.0) * dt);
  return Eigen::AngleAxisd(q_step.inverse() * q.normalized()).angle();
}

// Magnus: the true step is Exp(w0 dt + alpha dt^2/2 + O(dt^3)); holding w0 misses alpha dt^2/2.
double predictedRampError(const Eigen::Vector3d& /*w0*/, const Eigen::Vector3d& alpha, double dt) {
  return 0.5 * alpha.norm() * dt * dt;
}

// alpha dt^2 / 2 <= tol  <=>  dt <= sqrt(2 tol / alpha).
double maxStepForTolerance(double alpha, double tol) {
  return std::sqrt(2.0 * tol / std::abs(alpha));
}

}  // namespace ex57_2_3
