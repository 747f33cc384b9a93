// The rolling foot: a round foot's stance point that does not move (the kit's own addition; the
// chapter treats the foot as a point).
//
// A Go2-class foot is a sphere of radius r on the end of the calf, and leg kinematics give its
// centre c. The filters assume a stance foot stands still, but a sphere rolls while the calf
// turns over it: on the physics logs the centre moves at 0.05-0.06 m/s through every stance.
// Flat ground is assumed here, with world normal n = e_z (not true on a ramp or a step). It is
// for feet that roll: the analytic simulator's foot centres stay put in stance, and there this
// correction moves the point by 1.2 cm per stance instead (ESKF on the log of `legkit sim
// --scenario trot --duration 20`: position RMSE 0.045 m without it, 0.384 m with it). On the log
// of `legkit sim --scenario physics-trot --duration 60` it takes the ESKF's position RMSE from
// 1.31 m to 0.58 m and its ANEES from 859 to 30 (the log's contact flags, R the estimate's).
//
// Derivation. The sphere turns with the calf, at world angular velocity
//   w_calf = R (w + w_leg),   w_leg = dq1 e_x + Rx(q1) (dq2 + dq3) e_y     (body frame)
// (w the base rate from the gyro; abduction about x, hip and knee about y turned by the
// abduction). Its lowest point g = c - r n touches the ground. Rolling without slipping, that
// material point has zero velocity: dc/dt + w_calf x (-r n) = 0, so the centre moves at
//   v_roll = w_calf x (r n),
// and so does g (n is constant). The ground point touched at touchdown t0 is therefore
//   g0 = c - r n - s,   s(t) = integral from t0 to t of v_roll dt   (world),
// fixed in the world for as long as the sphere rolls without slipping. In the body frame, with
// n_b = R^T n and s_b = R^T s,
//   p_body' = c_b - r n_b - s_b.
// Its rate in the body frame follows from dR^T/dt = -[w]_x R^T and R^T v_roll = (w + w_leg) x r
// n_b:
//   v_body' = v_c + w x (r n_b + s_b) - (w + w_leg) x r n_b = v_c + w x s_b - w_leg x r n_b,
// with v_c = J(q) dq the centre's. Then the point's world velocity is zero:
//   v + R (w x p_body' + v_body') = dc/dt - v_roll = 0.
// s is integrated with the trapezoidal rule over the samples' dt and restarts at zero when a foot
// touches down (a foot not in stance at the previous apply()). R is the base attitude, in
// practice the estimator's previous estimate; only its tilt enters n_b, its yaw enters s_b.
//
// Fixed-size state (four feet): apply() never allocates.
#pragma once

#include <Eigen/Core>
#include <array>

#include "estimation/step_input.hpp"
#include "io/log.hpp"
#include "model/quadruped.hpp"

namespace legkit::leg_odometry {

class RollingFoot {
 public:
  // Throws std::invalid_argument for a negative or non-finite foot radius.
  explicit RollingFoot(const model::QuadrupedGeometry& geometry);

  // Every foot out of stance: the next stance of each foot starts a new touchdown.
  void reset();
  // For every stance foot of `in` (quadruped ids 0..3): p_body becomes the ground point the foot
  // sphere touched at touchdown (centre - r n minus the distance rolled since), v_body the velocity
  // that keeps it stationary (file comment); R is the base attitude (previous estimate), w the
  // base rate (the last gyro sample the estimators admitted, never a rejected one: a 1e6 rad/s
  // glitch would roll every foot away), q and dq the joint angles and rates of the same sample.
  // Throws std::invalid_argument for a foot id outside 0..3 or a stance foot without v_body (the
  // centre's velocity J dq), before anything changes.
  void apply(StepInput& in, const Eigen::Matrix3d& R, const Eigen::Vector3d& w,
             const io::JointVector& q, const io::JointVector& dq);

  // The world distance s rolled by foot `foot` since its touchdown (zero when not in stance).
  const Eigen::Vector3d& rolled(int foot) const { return s_[foot]; }

 private:
  static constexpr int kFeet = model::kNumLegs;
  double r_;                                   // foot radius [m]
  std::array<bool, kFeet> stance_{};           // stance at the previous apply()
  std::array<Eigen::Vector3d, kFeet> s_;       // rolled since touchdown, world [m]
  std::array<Eigen::Vector3d, kFeet> v_roll_;  // v_roll at the previous apply(), world [m/s]
};

}  // namespace legkit::leg_odometry
