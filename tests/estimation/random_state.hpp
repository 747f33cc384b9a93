// The nominal state the ESKF and the TSIF share (estimation/invariant/nominal_state.hpp), for their
// tests: random states, the exact constant-input motion between two of them (and the filters
// without contacts against it), unit errors.
#pragma once

#include <algorithm>
#include <random>
#include <vector>

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

// Without contacts (every sample's feet taken out of 2 s of the trot, seed 3) the ESKF or the
// TSIF is the exact strapdown motion with its zero bias, to 1e-9 in p, v and R; nothing
// observes the gyro bias (|b_g| <= bias_tolerance at every sample).
template <class Filter>
void checkDeadReckoningWithoutContacts(Filter& filter, double bias_tolerance) {
  const io::Log log = trotLog(2.0, 3, false);
  std::vector<StepInput> inputs = inputsOf(log);
  const EstimateSample x0 = eval::initialState(log);
  filter.reset(x0);
  invariant::nominal::State dr;  // dead reckoning with zero bias, the same exact step
  dr.R = lie::SO3d::fromQuaternion(x0.q);
  dr.v = x0.v;
  dr.p = x0.p;
  double worst = 0.0;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    inputs[k].num_contacts = 0;
    filter.step(inputs[k]);
    if (k > 0) dr = exactMotion(dr, inputs[k - 1].imu, inputs[k].dt);
    const invariant::nominal::State& x = filter.state();
    worst = std::max({worst, (x.p - dr.p).norm(), (x.v - dr.v).norm(), x.R.rminus(dr.R).norm()});
    REQUIRE(x.b_g.norm() <= bias_tolerance);
  }
  CHECK(worst < 1e-9);
}

// That a refused step left the nominal state as it was, bit for bit.
inline void checkSameState(const invariant::nominal::State& x,
                           const invariant::nominal::State& before) {
  CHECK(x.R.matrix() == before.R.matrix());
  CHECK(x.v == before.v);
  CHECK(x.p == before.p);
  for (std::size_t i = 0; i < x.d.size(); ++i) CHECK(x.d[i] == before.d[i]);
  CHECK(x.b_g == before.b_g);
  CHECK(x.b_a == before.b_a);
}

// h times the i-th unit error.
inline invariant::nominal::Vector27 unitError(int i, double h) {
  invariant::nominal::Vector27 e = invariant::nominal::Vector27::Zero();
  e(i) = h;
  return e;
}

}  // namespace legkit::test
