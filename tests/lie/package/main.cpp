// A consumer of the installed lie package: uses SO(3), SE_2(3), the run-time SE_K(3), the
// IMU propagation and the Ceres manifolds (component ceres), and returns 0 only if the results
// are right.
#include <cstdio>
#include <lie/ceres/manifolds.hpp>
#include <lie/lie.hpp>

int main() {
  lie::SE23d::Tangent xi;
  xi << 0.3, -0.2, 0.1, 1.0, 2.0, 3.0, -1.0, 0.5, 0.25;
  const double roundTrip = (lie::SE23d::Exp(xi).Log() - xi).norm();

  const lie::SO3d R = lie::SO3d::Exp(Eigen::Vector3d(0.0, 0.0, 1.5707963267948966));
  const double rotation = (R * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm();

  lie::SEKd<double, 4> X(2);
  X.appendColumn(Eigen::Vector3d(0.2, 0.1, -0.3));
  const Eigen::Vector3d g(0, 0, -9.81);
  // Free fall for 1 s from rest: p = g / 2.
  const auto Y = lie::imu::propagate(X, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), g, 1.0);
  const double fall = (Y.col(1) - 0.5 * g).norm();

  // lie::ceres: Minus(Plus(X, d), X) = d on the SE(3) manifold (R column-major, then t).
  const lie::ceres::SE3Manifold manifold;
  const lie::SE3d::Tangent d = xi.head<6>();
  const double x[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5, -0.5, 2.0};
  double x_plus_d[12];
  double back[6];
  const bool manifoldOk = manifold.Plus(x, d.data(), x_plus_d) && manifold.Minus(x_plus_d, x, back);
  const double manifoldRoundTrip = (Eigen::Map<const lie::SE3d::Tangent>(back) - d).norm();

  std::printf(
      "lie package: round trip %.2e, rotation %.2e, free fall %.2e, %ld columns, "
      "SE3Manifold round trip %.2e\n",
      roundTrip, rotation, fall, static_cast<long>(Y.numCols()), manifoldRoundTrip);
  const bool ok = roundTrip < 1e-14 && rotation < 1e-15 && fall < 1e-14 && Y.numCols() == 3 &&
                  manifoldOk && manifoldRoundTrip < 1e-14;
  return ok ? 0 : 1;
}
