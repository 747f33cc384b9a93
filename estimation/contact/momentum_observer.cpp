#include "estimation/contact/momentum_observer.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>

namespace legkit::contact {

namespace {

constexpr int kJ = model::kNumJointDof;
using StackedJacobian = Eigen::Matrix<double, 3 * model::kNumLegs, model::kNumDof>;  // J_c

}  // namespace

MomentumObserver::MomentumObserver(const model::QuadrupedGeometry& geometry,
                                   const model::QuadrupedInertia& inertia,
                                   const MomentumObserverParams& params)
    : dynamics_(geometry, inertia, params.gravity), params_(params) {
  if (!(params.K_O > 0.0) || !std::isfinite(params.K_O))
    throw std::invalid_argument("momentum-observer: K_O must be positive and finite");
  if (!(params.release <= params.threshold))
    throw std::invalid_argument("momentum-observer: release must not exceed threshold");
  if (!(params.settle_time >= 0.0))
    throw std::invalid_argument("momentum-observer: settle_time must be >= 0");
  for (int leg = 0; leg < model::kNumLegs; ++leg) damping_.segment<3>(3 * leg) = inertia.damping;
  reset();
}

void MomentumObserver::reset() {
  started_ = false;
  t_start_ = 0.0;
  M_prev_.setZero();
  nu_prev_.setZero();
  drive_prev_.setZero();
  p_hat_.setZero();
  r_.setZero();
  for (Eigen::Vector3d& l : lambda_) l.setZero();
  contact_.fill(false);
}

ContactEstimate MomentumObserver::update(const ContactSignals& signals) {
  if (signals.num_feet < 1 || signals.num_feet > kMaxFeet)
    throw std::invalid_argument("momentum-observer at t = " + std::to_string(signals.t) +
                                ": num_feet = " + std::to_string(signals.num_feet) +
                                " outside [1, " + std::to_string(kMaxFeet) + "]");
  if (!std::isfinite(signals.dt) || signals.dt < 0.0)
    throw std::invalid_argument("momentum-observer at t = " + std::to_string(signals.t) +
                                ": dt = " + std::to_string(signals.dt) +
                                " (must be finite and >= 0)");
  ContactEstimate out;
  out.t = signals.t;
  out.num_feet = signals.num_feet;
  const auto fail = [&](const char* why) {
    started_ = false;
    for (int i = 0; i < signals.num_feet; ++i) out.feet[i].problem = why;
    return out;
  };
  if (signals.num_feet != model::kNumLegs) return fail("not the built-in quadruped's four feet");
  if (!signals.has_joints) return fail("no joint angles");
  if (!signals.has_torque) return fail("no joint torques");
  if (!signals.base.valid) return fail("no base estimate");
  if (!signals.q.allFinite() || !signals.dq.allFinite() || !signals.tau.allFinite() ||
      !signals.gyro.allFinite() || !signals.base.R.allFinite() || !signals.base.v.allFinite())
    return fail("non-finite input");

  // nu = (v world from the previous estimate, omega body from the gyro, dq).
  model::FloatingBaseState x;
  x.R = signals.base.R;
  x.v = signals.base.v;
  x.omega = signals.gyro;
  x.q = signals.q;
  x.dq = signals.dq;
  const model::GeneralizedVector nu = x.nu();
  const model::GeneralizedMatrix M = dynamics_.massMatrix(x);
  const model::GeneralizedVector p = M * nu;  // generalized momentum
  // S^T tau - h, with tau the motor torque less the joints' viscous damping.
  model::GeneralizedVector drive = -dynamics_.biasForces(x);
  drive.tail<kJ>() += signals.tau - damping_.cwiseProduct(signals.dq);

  if (!started_ || signals.dt <= 0.0) {
    // p_0: the residual starts at zero.
    started_ = true;
    t_start_ = signals.t;
    p_hat_ = p;
    r_.setZero();
  } else {
    // Over [t_{k-1}, t_k]: Mdot nu = ((M_k - M_{k-1}) / dt) nu (nu averaged over the interval),
    // and the previous row's torques, which acted over that interval.
    const model::GeneralizedVector Mdot_nu = (M - M_prev_) * (0.5 * (nu + nu_prev_)) / signals.dt;
    p_hat_ += (drive_prev_ + Mdot_nu + r_) * signals.dt;
    r_ = params_.K_O * (p - p_hat_);
  }
  M_prev_ = M;
  nu_prev_ = nu;
  drive_prev_ = drive;

  // lambda = (J_c^T)^+ r = (J_c J_c^T)^-1 J_c r.
  StackedJacobian J;
  for (int leg = 0; leg < model::kNumLegs; ++leg)
    J.middleRows<3>(3 * leg) = dynamics_.footJacobian(leg, x);
  const Eigen::Matrix<double, 12, 1> lambda = (J * J.transpose()).ldlt().solve(J * r_);
  for (int leg = 0; leg < model::kNumLegs; ++leg) lambda_[leg] = lambda.segment<3>(3 * leg);

  const bool settling = signals.t - t_start_ < params_.settle_time;
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    FootContact& c = out.feet[leg];
    if (settling) {
      c.problem = "momentum observer converging";
      continue;
    }
    const double f_n = lambda_[leg].z();
    if (!std::isfinite(f_n)) {
      c.problem = "non-finite input";
      continue;
    }
    if (f_n > params_.threshold) contact_[leg] = true;
    if (f_n < params_.release) contact_[leg] = false;
    c.contact = contact_[leg];
    c.probability = c.contact ? 1.0 : 0.0;
    c.force = f_n;
  }
  return out;
}

}  // namespace legkit::contact
