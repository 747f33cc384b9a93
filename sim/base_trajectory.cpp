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

// Vertical motion of a bound relative to the nominal height: the gait alternates stance (of one
// leg pair, duty * period long) and flight, twice per period. In flight the base falls freely
// (z'' = -g exactly); in stance a quintic joins the landing state to the take-off state, which
// mirror each other (same height, opposite vertical speed, acceleration -g at both ends), so the
// whole profile is twice continuously differentiable and periodic.
Jet ballisticHeight(const Gait& gait, double t) {
  const double half = 0.5 * gait.period;
  const double stance = gait.duty * gait.period;
  const double flight = half - stance;
  const double v_takeoff = 0.5 * kGravity * flight;
  const double u = std::fmod(std::max(t - gait.start, 0.0), half);
  if (u < stance) {
    return quinticHermite(0.0, -v_takeoff, -kGravity, 0.0, v_takeoff, -kGravity, stance, u);
  }
  const double w = u - stance;
  return {v_takeoff * w - 0.5 * kGravity * w * w, v_takeoff - kGravity * w, -kGravity};
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
