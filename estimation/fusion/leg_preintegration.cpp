#include "estimation/fusion/leg_preintegration.hpp"

#include <sstream>
#include <stdexcept>

#include "estimation/imu/input_checks.hpp"
#include "lie/imu_dynamics.hpp"

namespace legkit::fusion {

LegPreintegrator::LegPreintegrator(const Eigen::Vector3d& b_g0, const Eigen::Vector3d& b_v0,
                                   const model::ImuNoise& noise)
    : b_g0_(b_g0), b_v0_(b_v0), noise_(noise) {
  imu::detail::requireFinite(b_g0, "LegPreintegrator", "linearisation gyro bias b_g0");
  imu::detail::requireFinite(b_v0, "LegPreintegrator", "linearisation velocity bias b_v0");
}

void LegPreintegrator::integrate(const Eigen::Vector3d& w_m, const Eigen::Vector3d& v,
                                 const Eigen::Matrix3d& Sigma_v, double dt) {
  imu::detail::requirePositiveStep(dt, "LegPreintegrator::integrate");
  imu::detail::requireFinite(w_m, "LegPreintegrator::integrate", "gyro reading w_m");
  imu::detail::requireFinite(v, "LegPreintegrator::integrate", "leg velocity v");
  if (!Sigma_v.allFinite() || !(Sigma_v.diagonal().minCoeff() >= 0.0) ||
      !((Sigma_v - Sigma_v.transpose()).cwiseAbs().maxCoeff() <=
        1e-12 * Sigma_v.cwiseAbs().maxCoeff())) {
    std::ostringstream os;
    os << "LegPreintegrator::integrate: velocity covariance Sigma_v must be finite, symmetric, "
          "with a non-negative diagonal, got\n"
       << Sigma_v;
    throw std::invalid_argument(os.str());
  }

  using Eigen::Matrix3d;
  using Eigen::Vector3d;
  const Vector3d w = w_m - b_g0_;  // w_k = w_m,k - b_g0
  const Vector3d u = v - b_v0_;    // v_k - b_v0
  const Vector3d phi = w * dt;
  const lie::AngleSeries<double> c(phi.squaredNorm());
  const Matrix3d E = lie::SO3d::Exp(phi).matrix();
  const Matrix3d Jr = lie::SO3d::Jr(phi);
  const Matrix3d G1 = lie::Gamma<1>(phi);
  const Matrix3d D1 = lie::imu::dGammaTimesVector<1>(phi, u, c) * dt;  // d(Gamma_1 u)/dw
  const Matrix3d R = dR_.matrix();                                     // dR_ik, before the step
  const Matrix3d RxG1u = R * lie::hat3(Vector3d(G1 * u));              // dR [Gamma_1 u]_x

  // Error dynamics of (dphi, dp): x_{k+1} = A x_k + B_g n_g + B_v n_v.
  Matrix6d A = Matrix6d::Identity();
  A.block<3, 3>(0, 0) = E.transpose();
  A.block<3, 3>(3, 0) = -RxG1u * dt;
  Eigen::Matrix<double, 6, 3> B_g, B_v;
  B_g << Jr * dt, R * D1 * dt;
  B_v << Matrix3d::Zero(), R * G1 * dt;
  const double var_g = noise_.gyroSampleSigma(dt) * noise_.gyroSampleSigma(dt);  // sigma_g^2/dt
  Sigma_ =
      (A * Sigma_ * A.transpose() + var_g * B_g * B_g.transpose() + B_v * Sigma_v * B_v.transpose())
          .eval();
  Sigma_ = (0.5 * (Sigma_ + Sigma_.transpose())).eval();
  Sigma_dp_ = Sigma_.block<3, 3>(3, 3);

  // Bias Jacobians (a bias change db enters as n = -db); dp first, it uses the old J_R_bg.
  J_p_bv_ -= R * G1 * dt;
  J_p_bg_ += -RxG1u * J_R_bg_ * dt - R * D1 * dt;
  J_R_bg_ = (E.transpose() * J_R_bg_ - Jr * dt).eval();

  // Increments, exact for a rate and a body velocity held over dt.
  dp_ += R * G1 * u * dt;
  dR_ = lie::SO3d::fromQuaternion(Eigen::Quaterniond(R * E));
  dt_ij_ += dt;
}

}  // namespace legkit::fusion
