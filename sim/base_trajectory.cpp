#include "sim/base_trajectory.hpp"

#include <cmath>

#include "lie/so3.hpp"
#include "sim/jet.hpp"

namespace legkit::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGravity = 9.81;

// amplitude * sin(2 pi f t), switched on smoothly by `ramp`.
Jet oscillation(double amplitude, double frequency, const Jet& ramp, double t) {
  if (amplitude == 0.0) return Jet::constant(0.0);
  return amplitude * (ramp * sin(2.0 * kPi * frequency * Jet::time(t)));
}

// Vertical motion of a bound relative to the nominal height. The gait alternates stance (of one
// leg pair, duty * period long) and flight, twice per period. In flight the base falls freely
// (z'' = -g exactly). In stance the legs push: z'' = -g + c phi(s), s = u / T_s, with the bump
// phi(s) = s^2 (1 - s)^2, whose value and slope vanish at both ends; c is chosen so that the
// stance turns the landing speed -v_0 into the take-off speed +v_0 = g T_f / 2:
//   c = 30 (2 v_0 + g T_s) / T_s          (the integral of phi over [0, 1] is 1/30).
// With Phi1(s) = s^3/3 - s^4/2 + s^5/5 and Phi2(s) = s^4/12 - s^5/10 + s^6/30 (its integrals):
//   z' = -v_0 - g u + c T_s Phi1(s),   z = -v_0 u - g u^2 / 2 + c T_s^2 Phi2(s),
// and z returns to 0 at take-off. Acceleration and jerk are continuous everywhere.
Jet ballisticHeight(const Gait& gait, double t) {
  const double half = 0.5 * gait.period;
  const double Ts = gait.duty * gait.period;  // stance
  const double Tf = half - Ts;                // flight
  const double v0 = 0.5 * kGravity * Tf;
  const double u = std::fmod(std::max(t - gait.start, 0.0), half);
  if (u < Ts) {
    const double c = 30.0 * (2.0 * v0 + kGravity * Ts) / Ts;
    const double s = u / Ts;
    const double s2 = s * s, s3 = s2 * s, s4 = s3 * s;
    const double phi = s2 * (1.0 - s) * (1.0 - s);
    const double Phi1 = s3 / 3.0 - s4 / 2.0 + s4 * s / 5.0;
    const double Phi2 = s4 / 12.0 - s4 * s / 10.0 + s4 * s2 / 30.0;
    return {-v0 * u - 0.5 * kGravity * u * u + c * Ts * Ts * Phi2,
            -v0 - kGravity * u + c * Ts * Phi1, -kGravity + c * phi};
  }
  const double w = u - Ts;
  return {v0 * w - 0.5 * kGravity * w * w, v0 - kGravity * w, -kGravity};
}

}  // namespace

BaseState BaseTrajectory::at(double t) const {
  const double t0 = s_.stand_time;
  const Jet ramp = smoothStep(t0, s_.ramp_duration, t);
  const Jet distance = smoothStepIntegral(t0, s_.ramp_duration, t);  // integral of the ramp

  Jet z = Jet::constant(s_.height) + oscillation(s_.bob_amplitude, s_.bob_frequency, ramp, t);
  if (s_.ballistic_flight) {
    Gait gait = s_.gait;
    gait.start = t0;
    z = z + ramp * ballisticHeight(gait, t);
  }
  const Jet x = s_.velocity.x() * distance;
  const Jet y = s_.velocity.y() * distance;
  const Jet yaw = s_.yaw_rate * distance + oscillation(s_.yaw_amplitude, s_.yaw_frequency, ramp, t);
  const Jet pitch = oscillation(s_.pitch_amplitude, s_.pitch_frequency, ramp, t);
  const Jet roll = oscillation(s_.roll_amplitude, s_.roll_frequency, ramp, t);

  BaseState b;
  b.p = {x.f, y.f, z.f};
  b.v = {x.d, y.d, z.d};
  b.a = {x.dd, y.dd, z.dd};
  b.yaw = yaw.f;
  using lie::SO3d;
  b.R =
      (SO3d::Exp(Eigen::Vector3d::UnitZ() * yaw.f) * SO3d::Exp(Eigen::Vector3d::UnitY() * pitch.f) *
       SO3d::Exp(Eigen::Vector3d::UnitX() * roll.f))
          .matrix();
  const double sr = std::sin(roll.f), cr = std::cos(roll.f);
  const double sp = std::sin(pitch.f), cp = std::cos(pitch.f);
  b.w = {roll.d - yaw.d * sp, pitch.d * cr + yaw.d * sr * cp, yaw.d * cr * cp - pitch.d * sr};
  return b;
}

}  // namespace legkit::sim
