#include "estimation/imu/dead_reckoning.hpp"

#include "estimation/imu/input_checks.hpp"
#include "lie/imu_dynamics.hpp"
#include "lie/sek3.hpp"

namespace legkit::imu {

NavState deadReckoningStep(const NavState& x, const model::ImuReading& m,
                           const model::ImuBias& b_hat, double dt, const Eigen::Vector3d& g) {
  detail::requirePositiveStep(dt, "deadReckoningStep");
  detail::requireFinite(m.w_m, "deadReckoningStep", "gyro reading w_m");
  detail::requireFinite(m.a_m, "deadReckoningStep", "accelerometer reading a_m");
  lie::SE23d::Columns C;
  C << x.v, x.p;
  const lie::SE23d X(x.R, C);
  // w = w_m - b_g, f = a_m - b_a; then R, v, p exactly over dt (lie/imu_dynamics.hpp).
  const lie::SE23d X_next = lie::imu::propagate(X, Eigen::Vector3d(m.w_m - b_hat.b_g),
                                                Eigen::Vector3d(m.a_m - b_hat.b_a), g, dt);
  return {X_next.rotation(), X_next.col(0), X_next.col(1)};
}

}  // namespace legkit::imu
