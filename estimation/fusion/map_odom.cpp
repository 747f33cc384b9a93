#include "estimation/fusion/map_odom.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>
#include <string>

#include "estimation/engineering/gating.hpp"

namespace legkit::fusion {
namespace {

using Matrix3d = Eigen::Matrix3d;
using Vector6d = Eigen::Matrix<double, 6, 1>;

void require(bool ok, const char* field, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("MapOdomOptions.") + field + ": expected " + expected);
  }
}

bool finitePose(const PoseMeasurement& z) {
  return std::isfinite(z.t) && std::isfinite(z.t_arrival) && z.R_MB.matrix().allFinite() &&
         z.p_MB.allFinite() && z.cov.allFinite();
}

}  // namespace

void checkMapOdomOptions(const MapOdomOptions& o) {
  require(std::isfinite(o.sigma_rotation_walk) && o.sigma_rotation_walk >= 0.0,
          "sigma_rotation_walk", "a finite density >= 0 [rad/sqrt(s)]");
  require(std::isfinite(o.sigma_position_walk) && o.sigma_position_walk >= 0.0,
          "sigma_position_walk", "a finite density >= 0 [m/sqrt(s)]");
  require(std::isfinite(o.n_sigma) && o.n_sigma > 0.0, "n_sigma", "a finite n > 0");
  require(std::isfinite(o.jump_confirm_time) && o.jump_confirm_time >= 0.0, "jump_confirm_time",
          "a finite time >= 0 [s]");
}

MapOdomAlignment::MapOdomAlignment(const MapOdomOptions& options)
    : options_((checkMapOdomOptions(options), options)),
      threshold_(
          engineering::chiSquareQuantile(6, engineering::nSigmaProbability(options.n_sigma))) {}

MapOdomAlignment::Observation MapOdomAlignment::observe(const PoseMeasurement& z,
                                                        const OdomPose& odom,
                                                        bool include_odom_covariance) {
  Observation obs;
  // Z = T_MB T_OB^-1 (the chapter's measurement of T_MO).
  obs.R_MO = z.R_MB * odom.R_OB.inverse();
  obs.p_MO = z.p_MB - obs.R_MO.matrix() * odom.p_OB;
  // Its covariance through the first-order error map derived in the header, computed as
  // J_Q (C_z + B C_o B^T) J_Q^T with J_Q = [[I, 0], [[q]x, I]] and B = diag(R_MO, R_MO)
  // (J_z = J_Q, J_o = -J_Q B), block by block: no 6x6 by 6x6 product.
  const Matrix3d R = obs.R_MO.matrix();
  const Matrix3d Q = lie::hat3(Eigen::Vector3d(z.p_MB - obs.p_MO));  // [q]x, q = R_MO p_OB
  obs.cov = z.cov;
  if (include_odom_covariance) {
    obs.cov.block<3, 3>(0, 0) += R * odom.cov.block<3, 3>(0, 0) * R.transpose();
    obs.cov.block<3, 3>(0, 3) += R * odom.cov.block<3, 3>(0, 3) * R.transpose();
    obs.cov.block<3, 3>(3, 0) += R * odom.cov.block<3, 3>(3, 0) * R.transpose();
    obs.cov.block<3, 3>(3, 3) += R * odom.cov.block<3, 3>(3, 3) * R.transpose();
  }
  obs.cov.bottomRows<3>() += Q * obs.cov.topRows<3>();              // J_Q C
  obs.cov.rightCols<3>() += obs.cov.leftCols<3>() * Q.transpose();  // (J_Q C) J_Q^T
  obs.cov = 0.5 * (obs.cov + obs.cov.transpose()).eval();
  return obs;
}

MapOdomAlignment::Outcome MapOdomAlignment::update(const PoseMeasurement& z,
                                                   const OdomHistory& odometry) {
  // The checks that need no odometry come first, so that a bad pose is named for what it is.
  if (!z.valid) return count(Outcome::kInvalid);
  if (!finitePose(z)) return count(Outcome::kNonFinite);
  const OdomHistory::Result odom = odometry.at(z.t);
  switch (odom.status) {
    case OdomHistory::Lookup::kOk:
      return update(z, odom.pose);
    case OdomHistory::Lookup::kTooOld:
      return count(Outcome::kTooOld);
    case OdomHistory::Lookup::kEmpty:
    case OdomHistory::Lookup::kInFuture:
      return count(Outcome::kInFuture);
    case OdomHistory::Lookup::kNotFinite:
      break;
  }
  return count(Outcome::kNonFinite);
}

MapOdomAlignment::Outcome MapOdomAlignment::update(const PoseMeasurement& z, const OdomPose& odom) {
  if (!z.valid) return count(Outcome::kInvalid);
  if (!finitePose(z) || !odom.R_OB.matrix().allFinite() || !odom.p_OB.allFinite() ||
      !odom.cov.allFinite()) {
    return count(Outcome::kNonFinite);
  }
  if (odom.t != z.t) {
    throw std::invalid_argument(
        "MapOdomAlignment::update: the odometry pose is at t = " + std::to_string(odom.t) +
        ", the pose's stamp is " + std::to_string(z.t) + " (use the odometry at the pose's stamp)");
  }
  if (Eigen::LLT<Matrix6d>(z.cov).info() != Eigen::Success) return count(Outcome::kBadCovariance);
  if (!(z.t > t_)) return count(Outcome::kOutOfOrder);

  const Observation obs = observe(z, odom, options_.include_odom_covariance);
  if (!initialised_) {
    R_MO_ = obs.R_MO;
    p_MO_ = obs.p_MO;
    P_ = obs.cov;
    t_ = z.t;
    initialised_ = true;
    return count(Outcome::kInitialised);
  }

  // Predict: the random walk of T_MO from the previous stamp (time passes for a gated pose too).
  const double dt = z.t - t_;
  t_ = z.t;
  const double q_r = options_.sigma_rotation_walk * options_.sigma_rotation_walk * dt;
  const double q_p = options_.sigma_position_walk * options_.sigma_position_walk * dt;
  P_.diagonal() += (Vector6d() << q_r, q_r, q_r, q_p, q_p, q_p).finished();

  // Innovation in the (dtheta, dp) convention: Z = (Exp(r_theta) R_MO_hat, p_MO_hat + r_p).
  Vector6d r;
  r.head<3>() = (obs.R_MO * R_MO_.inverse()).Log();
  r.tail<3>() = obs.p_MO - p_MO_;
  const Matrix6d S = P_ + obs.cov;
  const Eigen::LLT<Matrix6d> S_llt(S);
  if (S_llt.info() != Eigen::Success) return count(Outcome::kBadCovariance);
  const double d2 = r.dot(S_llt.solve(r));
  if (!std::isfinite(d2)) return count(Outcome::kNonFinite);
  last_d2_ = d2;

  Outcome outcome = Outcome::kUsed;
  if (options_.gating && d2 > threshold_) {
    if (std::isnan(gated_since_)) gated_since_ = z.t;
    if (z.t - gated_since_ < options_.jump_confirm_time) return count(Outcome::kGated);
    outcome = Outcome::kJumpUpdate;  // a confirmed jump: taken at the filter's own gain
  } else {
    gated_since_ = std::numeric_limits<double>::quiet_NaN();
  }

  // K = P S^-1 (S and P symmetric), the correction, the Joseph-form covariance.
  const Matrix6d K = S_llt.solve(P_).transpose();
  const Vector6d delta = K * r;
  R_MO_ = lie::SO3d::Exp(delta.head<3>()) * R_MO_;
  p_MO_ += delta.tail<3>();
  const Matrix6d I_K = Matrix6d::Identity() - K;
  P_ = I_K * P_ * I_K.transpose() + K * obs.cov * K.transpose();
  P_ = 0.5 * (P_ + P_.transpose()).eval();
  return count(outcome);
}

MapPose MapOdomAlignment::mapPose(const lie::SO3d& R_OB, const Eigen::Vector3d& p_OB) const {
  // T_MB = T_MO T_OB.
  return {R_MO_ * R_OB, R_MO_.matrix() * p_OB + p_MO_};
}

MapOdomAlignment::Outcome MapOdomAlignment::count(Outcome outcome) {
  switch (outcome) {
    case Outcome::kInitialised:
      ++counts_.initialised;
      break;
    case Outcome::kUsed:
      ++counts_.used;
      break;
    case Outcome::kJumpUpdate:
      ++counts_.jump_updates;
      break;
    case Outcome::kGated:
      ++counts_.gated;
      break;
    case Outcome::kInvalid:
      ++counts_.invalid;
      break;
    case Outcome::kNonFinite:
      ++counts_.non_finite;
      break;
    case Outcome::kBadCovariance:
      ++counts_.bad_covariance;
      break;
    case Outcome::kOutOfOrder:
      ++counts_.out_of_order;
      break;
    case Outcome::kTooOld:
      ++counts_.too_old;
      break;
    case Outcome::kInFuture:
      ++counts_.in_future;
      break;
  }
  return outcome;
}

const char* toString(MapOdomAlignment::Outcome outcome) {
  using O = MapOdomAlignment::Outcome;
  switch (outcome) {
    case O::kInitialised:
      return "initialised";
    case O::kUsed:
      return "used";
    case O::kJumpUpdate:
      return "used after a confirmed jump (ungated)";
    case O::kGated:
      return "gated";
    case O::kInvalid:
      return "invalid flag";
    case O::kNonFinite:
      return "non-finite";
    case O::kBadCovariance:
      return "covariance not positive definite";
    case O::kOutOfOrder:
      return "out of order";
    case O::kTooOld:
      return "older than the odometry history";
    case O::kInFuture:
      return "after the newest odometry";
  }
  return "?";
}

}  // namespace legkit::fusion
