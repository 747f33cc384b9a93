// The IMU module on the simulator's logs (sim/, legkit::sim): the 57.1 drift table on the
// "stand" scenario, and the preintegrated keyframe constraint against simulated true states.
#include <catch2/catch.hpp>
#include <cmath>

#include "estimation/imu/log_drift.hpp"
#include "estimation/imu/preintegration.hpp"
#include "sim/simulator.hpp"

using legkit::imu::deadReckoningDriftOnLog;
using legkit::imu::driftAt;
using legkit::model::ImuBias;

namespace {

legkit::sim::SimResult standLog(const ImuBias& bias, double duration) {
  legkit::sim::SimOptions o;
  o.scenario = legkit::sim::scenarioByName("stand");
  o.duration = duration;
  o.noiseless();
  o.initial_bias = bias;
  return legkit::sim::simulate(o);
}

// Worst keyframe-constraint error over 0.2 s keyframes of a noiseless simulated trot at `rate`.
struct ConstraintError {
  double p = 0.0, v = 0.0, R = 0.0;
};

ConstraintError trotConstraintError(double rate) {
  legkit::sim::SimOptions o;
  o.duration = 4.0;
  o.rate = rate;
  o.noiseless();
  const auto& rows = legkit::sim::simulate(o).log.rows;
  const std::size_t keyframe = static_cast<std::size_t>(std::lround(0.2 * rate));
  ConstraintError worst;
  for (std::size_t i = static_cast<std::size_t>(2.0 * rate); i + keyframe < rows.size();
       i += keyframe) {
    legkit::imu::Preintegrator pre;
    for (std::size_t k = i; k < i + keyframe; ++k)
      pre.integrate({rows[k].gyro, rows[k].acc}, rows[k + 1].t - rows[k].t);
    const legkit::imu::NavState x_i{lie::SO3d::fromQuaternion(rows[i].gt_q), rows[i].gt_v,
                                    rows[i].gt_p};
    const auto x_j = pre.predict(x_i, ImuBias{});
    const auto& r_j = rows[i + keyframe];
    worst.p = std::max(worst.p, (x_j.p - r_j.gt_p).norm());
    worst.v = std::max(worst.v, (x_j.v - r_j.gt_v).norm());
    worst.R = std::max(worst.R, lie::SO3d::fromQuaternion(r_j.gt_q).rminus(x_j.R).norm());
  }
  return worst;
}

}  // namespace

TEST_CASE("57.1 drift table on the simulated stand scenario", "[sim][drift]") {
  // The stand scenario sways (height, roll, pitch, yaw) over fixed feet; readings are exact
  // samples, so besides the bias only the hold-per-sample discretisation enters.
  const auto sim = standLog({Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, 0.0, 0.0)}, 60.001);
  const auto drift = deadReckoningDriftOnLog(sim.log, ImuBias{}, 1.0);
  for (double t : {1.0, 10.0, 60.0}) {
    const auto s = driftAt(drift, t);
    INFO("t = " << t << " s: |dp| = " << s.position_error << " m, |dv| = " << s.velocity_error
                << " m/s, dtheta = " << s.attitude_error_deg << " deg");
    CHECK(s.position_error == Approx(0.005 * t * t).epsilon(0.01));  // measured: within 0.12 %
  }
}

TEST_CASE("57.1 gyro bias on the simulated stand scenario: 34 deg after 60 s", "[sim][drift]") {
  const auto sim = standLog({Eigen::Vector3d(0.0, 0.0, 0.01), Eigen::Vector3d::Zero()}, 60.001);
  const auto drift = deadReckoningDriftOnLog(sim.log, ImuBias{}, 10.0);
  const auto s = driftAt(drift, 60.0);
  INFO("|dp| = " << s.position_error << " m, dtheta = " << s.attitude_error_deg << " deg");
  CHECK(s.attitude_error_deg == Approx(34.38).epsilon(0.01));  // measured: 34.33 deg
}

TEST_CASE("57.2 preintegration between keyframes reproduces the simulated trot",
          "[sim][preintegration]") {
  // The simulator's readings are point samples of a changing motion; holding each for one
  // period costs O(dt), so the constraint error must be small and halve with the period.
  const ConstraintError e1 = trotConstraintError(1000.0), e2 = trotConstraintError(2000.0);
  INFO("1 kHz: |dp| " << e1.p << " m, |dv| " << e1.v << " m/s, dphi " << e1.R << " rad");
  INFO("2 kHz: |dp| " << e2.p << " m, |dv| " << e2.v << " m/s, dphi " << e2.R << " rad");
  CHECK(e1.p < 2e-3);
  CHECK(e1.v < 1e-2);
  CHECK(e1.R < 1e-3);
  CHECK(e1.p / e2.p == Approx(2.0).epsilon(0.15));
  CHECK(e1.v / e2.v == Approx(2.0).epsilon(0.15));
  CHECK(e1.R / e2.R == Approx(2.0).epsilon(0.15));
}
