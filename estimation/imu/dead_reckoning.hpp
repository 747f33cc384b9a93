// Dead reckoning (section 57.1): pure strapdown integration of IMU readings, no other sensor.
// With the bias-corrected rate w = w_m - b_g and specific force f = a_m - b_a held over dt,
//   dR/dt = R [w]_x,   dv/dt = R f + g,   dp/dt = v,
// has the exact solution that lie::imu::propagate computes on SE_2(3) (columns v, p). Any bias
// the caller's estimate b_hat misses is integrated once into attitude, once into velocity and
// twice into position: the drift of section 57.1.
#pragma once

#include <Eigen/Core>

#include "estimation/imu/nav_state.hpp"
#include "model/imu_model.hpp"

namespace legkit::imu {

// One exact constant-input step from x with reading m, bias estimate b_hat and gravity g.
// Throws std::invalid_argument for dt <= 0 or a NaN reading.
NavState deadReckoningStep(const NavState& x, const model::ImuReading& m,
                           const model::ImuBias& b_hat, double dt,
                           const Eigen::Vector3d& g = model::gravity());

}  // namespace legkit::imu
