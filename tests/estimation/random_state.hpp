// The nominal state the ESKF and the TSIF share (estimation/invariant/nominal_state.hpp), for their
// tests: random states, the exact constant-input motion between two of them, unit errors.
#pragma once

#include <random>

#include "estimation/invariant/nominal_state.hpp"
#include "filter_family.hpp"
#include "lie/imu_dynamics.hpp"
#include "lie/sek3.hpp"
#include "lie/so3.hpp"
#include "model/imu_model.hpp"

namespace legkit::test {

// A state far from the origin in every block, so that no term of a Jacobian vanishes by chance.
inline invariant::nominal::State randomState(std::mt19937& gen) {
  invariant::nominal::State x;
  x.R = lie::SO3d::Random(gen);
  x.v = normal3(gen, 1.0);
  x.p = normal3(gen, 2.0);
  for (Eigen::Vector3d& d : x.d) d = normal3(gen, 2.0);
  x.b_g = normal3(gen, 0.05);
  x.b_a = normal3(gen, 0.3);
  return x;
}

// x1 from x0 by an independent route: the exact constant-input motion on SE_2(3)
// (lie::imu::propagate), which the strapdown step and the TSIF's IMU residual describe.
inline invariant::nominal::State exactMotion(const invariant::nominal::State& x0,
                                             const model::ImuReading& u, double dt) {
  lie::SE23d::Columns C;
  C << x0.v, x0.p;
  const lie::SE23d X1 = lie::imu::propagate(lie::SE23d(x0.R, C), Eigen::Vector3d(u.w_m - x0.b_g),
                                            Eigen::Vector3d(u.a_m - x0.b_a), model::gravity(), dt);
  invariant::nominal::State x1 = x0;
  x1.R = X1.rotation();
  x1.v = X1.col(0);
  x1.p = X1.col(1);
  return x1;
}

// h times the i-th unit error.
inline invariant::nominal::Vector27 unitError(int i, double h) {
  invariant::nominal::Vector27 e = invariant::nominal::Vector27::Zero();
  e(i) = h;
  return e;
}

}  // namespace legkit::test
