#include "sim/locomotion_controller.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "model/imu_model.hpp"
#include "sim/jet.hpp"

namespace legkit::sim {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using WlsMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3 * model::kNumLegs,
                                3 * model::kNumLegs>;
using WlsVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3 * model::kNumLegs, 1>;

Eigen::Matrix3d skew(const Eigen::Vector3d& r) {
  Eigen::Matrix3d S;
  S << 0.0, -r.z(), r.y(), r.z(), 0.0, -r.x(), -r.y(), r.x(), 0.0;
  return S;
}

Eigen::Matrix3d yawRotation(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

double headingOf(const Eigen::Matrix3d& R) {
  return std::atan2(R(1, 0), R(0, 0));
}

// First index of leg's joints in a JointVector (3 * leg).
Eigen::Index legIndex(int leg) {
  return Eigen::Index{io::kJointsPerLeg} * leg;
}

// 64 s^3 (1 - s)^3 and its time derivative (sim/quadruped_motion.cpp's lift profile).
Eigen::Vector2d lift(double s, double T) {
  const double r = 1.0 - s;
  return {64.0 * s * s * s * r * r * r, 192.0 * s * s * r * r * (1.0 - 2.0 * s) / T};
}

}  // namespace

LocomotionController::LocomotionController(const model::QuadrupedKinematics& kinematics,
                                           double mass, const LocomotionCommand& command,
                                           const ControllerState& initial,
                                           const ControllerGains& gains)
    : kinematics_(kinematics),
      mass_(mass),
      command_(command),
      gains_(gains),
      t_last_(0.0),
      yaw_des_(headingOf(initial.R)) {
  const model::QuadrupedGeometry& g = kinematics_.geometry();
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    nominal_[leg] = {g.hip_offset[leg].x(),
                     g.hip_offset[leg].y() + model::lateralSign(leg) * g.abduction_offset, 0.0};
    const Eigen::Vector3d foot =
        initial.p + initial.R * kinematics_.footPosition(leg, initial.q.segment<3>(legIndex(leg)));
    lift_off_[leg] = foot;
    ground_[leg] = foot.z() - g.foot_radius;
    stance_[leg] = true;
    f_[leg].setZero();
  }
}

io::JointVector LocomotionController::torques(double t, const ControllerState& s,
                                              const io::JointVector& leg_bias) {
  // Time since the last call, counted from t = 0 only: the integral terms (and the desired yaw)
  // start at t = 0, whatever a settle before it did.
  const double dt = std::clamp(t, 0.0, std::max(t - t_last_, 0.0));
  t_last_ = t;
  const double radius = kinematics_.geometry().foot_radius;
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    const Eigen::Vector3d q = s.q.segment<3>(legIndex(leg));
    const Eigen::Vector3d dq = s.dq.segment<3>(legIndex(leg));
    const Eigen::Vector3d r_body = kinematics_.footPosition(leg, q);
    const Eigen::Matrix3d J_body = kinematics_.footJacobian(leg, q);
    J_[leg] = s.R * J_body;
    foot_p_[leg] = s.p + s.R * r_body;
    foot_v_[leg] = s.v + s.R * (s.omega.cross(r_body) + J_body * dq);
    const bool stance = gaitPhase(command_.gait, leg, t).stance;
    if (stance_[leg] && !stance) {  // lift-off: remember where the foot stood
      lift_off_[leg] = foot_p_[leg];
      ground_[leg] = foot_p_[leg].z() - radius;
    }
    stance_[leg] = stance;
  }

  distribute(s, desiredWrench(t, dt, s));

  io::JointVector tau = leg_bias;
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    Eigen::Vector3d foot_force;  // what the leg pushes on the world with
    if (stance_[leg]) {
      foot_force = -f_[leg];
      // Damp the foot's horizontal velocity relative to the base against the one the command
      // implies for a planted foot, -(v* + omega* x r): a sliding foot is carried with the base.
      const Eigen::Vector3d r = foot_p_[leg] - s.p;
      Eigen::Vector3d dv =
          foot_v_[leg] - s.v + v_cmd_world_ + Eigen::Vector3d(0.0, 0.0, yaw_rate_cmd_).cross(r);
      dv.z() = 0.0;
      foot_force -= gains_.kd_stance * dv;
    } else {
      const GaitPhase phase = gaitPhase(command_.gait, leg, t);
      const double T = phase.end - phase.begin;
      const double u = std::clamp(t - phase.begin, 0.0, T);
      const Eigen::Vector3d target = foothold(leg, t, phase.end, s);
      Eigen::Vector3d p_d, v_d;
      for (int i = 0; i < 3; ++i) {
        const Jet c = quinticHermite(lift_off_[leg](i), 0.0, 0.0, target(i), 0.0, 0.0, T, u);
        p_d(i) = c.f;
        v_d(i) = c.d;
      }
      const Eigen::Vector2d h = lift(u / T, T);
      p_d.z() += command_.swing_height * h(0);
      v_d.z() += command_.swing_height * h(1);
      foot_force = gains_.kp_swing * (p_d - foot_p_[leg]) + gains_.kd_swing * (v_d - foot_v_[leg]);
    }
    tau.segment<3>(legIndex(leg)) += J_[leg].transpose() * foot_force;
  }
  return tau;
}

Vector6d LocomotionController::desiredWrench(double t, double dt, const ControllerState& s) {
  const Jet ramp = smoothStep(command_.gait.start, command_.ramp_duration, t);
  const Eigen::Vector2d v_cmd = command_.velocity * ramp.f;
  const Eigen::Vector2d a_cmd = command_.velocity * ramp.d;
  const double yaw_rate = command_.yaw_rate * ramp.f;
  yaw_des_ += yaw_rate * dt;
  yaw_rate_cmd_ = yaw_rate;

  // Speeds in the heading frame (yaw of the measured attitude).
  const Eigen::Matrix3d H = yawRotation(headingOf(s.R));
  const Eigen::Vector3d v_h = H.transpose() * s.v;
  v_cmd_world_ = H * Eigen::Vector3d(v_cmd.x(), v_cmd.y(), 0.0);
  const double ex = v_cmd.x() - v_h.x();
  v_error_integral_ += ex * dt;
  lateral_error_ += (v_h.y() - v_cmd.y()) * dt;
  double ground = 0.0;
  for (double z : ground_) ground += z / model::kNumLegs;

  Eigen::Vector3d a_h(
      a_cmd.x() + gains_.kv_x * ex + gains_.ki_x * v_error_integral_,
      a_cmd.y() - gains_.kp_y * lateral_error_ + gains_.kd_y * (v_cmd.y() - v_h.y()),
      gains_.kp_z * (ground + command_.height - s.p.z()) - gains_.kd_z * s.v.z());
  if (command_.gait.alwaysStance()) {
    // Standing: keep the base over the centre of its feet, wherever they are (after a push on ice
    // they are not where they started).
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : foot_p_) centre += p / model::kNumLegs;
    const Eigen::Vector3d e = H.transpose() * (s.p - centre);
    a_h.head<2>() = -gains_.kp_y * e.head<2>() - gains_.kd_y * v_h.head<2>();
  }
  Vector6d w;
  w.head<3>() = mass_ * (H * a_h - model::gravity());  // F = m (a_des - g)
  // The feet cannot push sideways harder than the assumed friction allows: ask for no more, so
  // that the split's normal forces do not balance tangential forces the clamp would remove.
  const double f_xy = w.head<2>().norm(), f_xy_max = command_.mu_assumed * std::max(w.z(), 0.0);
  if (f_xy > f_xy_max) w.head<2>() *= f_xy_max / f_xy;

  const Eigen::AngleAxisd error(yawRotation(yaw_des_) * s.R.transpose());  // R_des R^T
  const Eigen::Vector3d omega_error = Eigen::Vector3d(0.0, 0.0, yaw_rate) - s.R * s.omega;
  w.tail<3>() = gains_.kp_R.cwiseProduct(error.angle() * error.axis()) +
                gains_.kd_R.cwiseProduct(omega_error);
  return w;
}

void LocomotionController::distribute(const ControllerState& s, const Vector6d& wrench) {
  std::array<int, model::kNumLegs> legs{};
  int n = 0;
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    f_[leg].setZero();
    if (stance_[leg]) legs[n++] = leg;
  }
  // A foot cannot pull: while the split asks a foot for a negative normal force, drop the foot
  // asking for the most negative one and split again over the others (an active set).
  WlsVector f;
  while (n > 0) {
    const Eigen::Index size = Eigen::Index{3} * n;
    Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 3 * model::kNumLegs> A(6, size);
    for (int k = 0; k < n; ++k) {
      A.block<3, 3>(0, Eigen::Index{3} * k).setIdentity();
      A.block<3, 3>(3, Eigen::Index{3} * k) = skew(foot_p_[legs[k]] - s.p);
    }
    // Normal equations of min (A f - w)^T S (A f - w) + alpha |f|^2.
    const WlsMatrix H = A.transpose() * gains_.wrench_weight.asDiagonal() * A +
                        gains_.alpha * WlsMatrix::Identity(size, size);
    const WlsVector b = A.transpose() * gains_.wrench_weight.asDiagonal() * wrench;
    f = Eigen::LDLT<WlsMatrix>(H).solve(b);
    // Normal (z) component of foot k's force in the split.
    const auto normal = [&f](int k) { return f(Eigen::Index{3} * k + 2); };
    int worst = -1;
    for (int k = 0; k < n; ++k) {
      if (normal(k) < 0.0 && (worst < 0 || normal(k) < normal(worst))) worst = k;
    }
    if (worst < 0) break;
    std::copy(legs.begin() + worst + 1, legs.begin() + n, legs.begin() + worst);
    --n;
  }
  for (int k = 0; k < n; ++k) {
    Eigen::Vector3d fk = f.segment<3>(Eigen::Index{3} * k);
    fk.z() = std::min(fk.z(), gains_.f_max);
    const double ft = fk.head<2>().norm();
    const double ft_max = command_.mu_assumed * fk.z();
    if (ft > ft_max) fk.head<2>() *= ft_max / ft;
    f_[legs[k]] = fk;
  }
}

Eigen::Vector3d LocomotionController::foothold(int leg, double t, double touchdown,
                                               const ControllerState& s) const {
  const Jet ramp = smoothStep(command_.gait.start, command_.ramp_duration, t);
  const Eigen::Vector3d v_cmd = yawRotation(headingOf(s.R)) *
                                Eigen::Vector3d(command_.velocity.x(), command_.velocity.y(), 0.0) *
                                ramp.f;
  const Eigen::Vector3d v(s.v.x(), s.v.y(), 0.0);
  const double stance = command_.gait.duty * command_.gait.period;
  // Where the hip will be at the middle of the next stance, plus the Raibert correction.
  const double ahead = std::max(touchdown - t, 0.0) + 0.5 * stance;
  const double yaw = headingOf(s.R) + command_.yaw_rate * ramp.f * ahead;
  Eigen::Vector3d p =
      s.p + v * ahead + yawRotation(yaw) * nominal_[leg] + gains_.k_raibert * (v - v_cmd);
  p.z() = ground_[leg] + kinematics_.geometry().foot_radius;
  return p;
}

}  // namespace legkit::sim
