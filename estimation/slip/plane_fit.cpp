#include "estimation/slip/plane_fit.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace legkit::slip {

GroundPlane fitGroundPlane(const Eigen::Vector3d* feet_world, int n, double collinear_tol) {
  if (n < 0 || (n > 0 && feet_world == nullptr)) {
    throw std::invalid_argument("fitGroundPlane: n must be >= 0 with a non-null array, got n = " +
                                std::to_string(n));
  }
  GroundPlane plane;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    if (!feet_world[i].allFinite()) {
      throw std::invalid_argument("fitGroundPlane: foothold " + std::to_string(i) +
                                  " is not finite");
    }
    mean += feet_world[i];
  }
  if (n == 0) return plane;
  mean /= n;
  plane.a = mean.z();
  if (n < 3) return plane;

  // Centred normal equations: M (b, c) = m, M the (x, y) scatter.
  Eigen::Matrix2d M = Eigen::Matrix2d::Zero();
  Eigen::Vector2d m = Eigen::Vector2d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d d = feet_world[i] - mean;
    M += d.head<2>() * d.head<2>().transpose();
    m += d.head<2>() * d.z();
  }
  // Smallest singular value of the centred (x, y) points = sqrt(smallest eigenvalue of M).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(M, Eigen::EigenvaluesOnly);
  plane.spread = std::sqrt(std::max(eig.eigenvalues()(0), 0.0) / n);
  if (plane.spread < collinear_tol) {
    plane.status = GroundPlane::kCollinear;
    return plane;
  }
  const Eigen::Vector2d bc = M.ldlt().solve(m);
  plane.b = bc(0);
  plane.c = bc(1);
  plane.a = mean.z() - plane.b * mean.x() - plane.c * mean.y();
  plane.normal = Eigen::Vector3d(-plane.b, -plane.c, 1.0).normalized();
  plane.slope = std::atan(std::hypot(plane.b, plane.c));
  double ss = 0.0;
  for (int i = 0; i < n; ++i) {
    const double e = feet_world[i].z() - plane.height(feet_world[i].x(), feet_world[i].y());
    ss += e * e;
  }
  plane.rms = std::sqrt(ss / n);
  plane.status = GroundPlane::kOk;
  return plane;
}

}  // namespace legkit::slip
