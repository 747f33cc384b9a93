#include "estimation/imu/preintegration.hpp"

#include "estimation/imu/input_checks.hpp"
#include "lie/imu_dynamics.hpp"

namespace legkit::imu {

Preintegrator::Preintegrator(const model::ImuBias& b0, const model::ImuNoise& noise)
    : b0_(b0), noise_(noise) {
  detail::requireFinite(b0.b_g, "Preintegrator", "linearisation gyro bias b_g");
  detail::requireFinite(b0.b_a, "Preintegrator", "linearisation accelerometer bias b_a");
}

void Preintegrator::integrate(const model::ImuReading& m, double dt) {
  detail::requirePositiveStep(dt, "Preintegrator::integrate");
  detail::requireFinite(m.w_m, "Preintegrator::integrate", "gyro reading w_m");
  detail::requireFinite(m.a_m, "Preintegrator::integrate", "accelerometer reading a_m");

  using Eigen::Matrix3d;
  using Eigen::Vector3d;
  const Vector3d w = m.w_m - b0_.b_g;  // w_k = w_m,k - b_g^0
  const Vector3d a = m.a_m - b0_.b_a;  // a_k = a_m,k - b_a^0
  const Vector3d phi = w * dt;
  const lie::AngleSeries<double> c(phi.squaredNorm());
  const lie::SO3d E = lie::SO3d::Exp(phi);
  const Matrix3d Et = E.matrix().transpose();
  const Matrix3d Jr = lie::SO3d::Jr(phi);
  const Matrix3d G1 = lie::Gamma<1>(phi);
  const Matrix3d G2 = lie::Gamma<2>(phi);
  // d(Gamma_m(phi) a)/dw = d(Gamma_m a)/dphi * dt
  const Matrix3d D1 = lie::imu::dGammaTimesVector<1>(phi, a, c) * dt;
  const Matrix3d D2 = lie::imu::dGammaTimesVector<2>(phi, a, c) * dt;
  const Matrix3d R = delta_.dR.matrix();  // dR before the update
  const double dt2 = dt * dt;

  // Error dynamics of (dphi, dv, dp): x_{k+1} = A x_k + B_g n_g + B_a n_a.
  const Matrix3d Rx1 = R * lie::hat3(Vector3d(G1 * a));  // dR [Gamma_1 a]_x
  const Matrix3d Rx2 = R * lie::hat3(Vector3d(G2 * a));  // dR [Gamma_2 a]_x
  Matrix9d A = Matrix9d::Identity();
  A.block<3, 3>(0, 0) = Et;
  A.block<3, 3>(3, 0) = -Rx1 * dt;
  A.block<3, 3>(6, 0) = -Rx2 * dt2;
  A.block<3, 3>(6, 3) = Matrix3d::Identity() * dt;
  Eigen::Matrix<double, 9, 3> B_g, B_a;
  B_g << Jr * dt, R * D1 * dt, R * D2 * dt2;
  B_a << Matrix3d::Zero(), R * G1 * dt, R * G2 * dt2;
  const double var_g = noise_.gyroSampleSigma(dt) * noise_.gyroSampleSigma(dt);    // sigma_g^2/dt
  const double var_a = noise_.accelSampleSigma(dt) * noise_.accelSampleSigma(dt);  // sigma_a^2/dt
  Sigma_ =
      (A * Sigma_ * A.transpose() + var_g * B_g * B_g.transpose() + var_a * B_a * B_a.transpose())
          .eval();
  Sigma_ = (0.5 * (Sigma_ + Sigma_.transpose())).eval();

  // Bias Jacobians (a bias change db enters as n = -db): position first, it uses the old ones.
  J_p_ba_ += J_v_ba_ * dt - R * G2 * dt2;
  J_p_bg_ += J_v_bg_ * dt - Rx2 * J_R_bg_ * dt2 - R * D2 * dt2;
  J_v_ba_ -= R * G1 * dt;
  J_v_bg_ += -Rx1 * J_R_bg_ * dt - R * D1 * dt;
  J_R_bg_ = (Et * J_R_bg_ - Jr * dt).eval();

  // Increments, exact for input held over dt.
  delta_.dp += delta_.dv * dt + R * G2 * a * dt2;
  delta_.dv += R * G1 * a * dt;
  delta_.dR = lie::SO3d::fromQuaternion(Eigen::Quaterniond(R * E.matrix()));
  dt_ij_ += dt;
}

PreintegratedDelta Preintegrator::corrected(const model::ImuBias& b) const {
  detail::requireFinite(b.b_g, "Preintegrator::corrected", "gyro bias b_g");
  detail::requireFinite(b.b_a, "Preintegrator::corrected", "accelerometer bias b_a");
  const Eigen::Vector3d db_g = b.b_g - b0_.b_g;
  const Eigen::Vector3d db_a = b.b_a - b0_.b_a;
  return {delta_.dR * lie::SO3d::Exp(J_R_bg_ * db_g),    // dR Exp(J_R_bg db_g)
          delta_.dv + J_v_bg_ * db_g + J_v_ba_ * db_a,   // dv + J_v_bg db_g + J_v_ba db_a
          delta_.dp + J_p_bg_ * db_g + J_p_ba_ * db_a};  // dp + J_p_bg db_g + J_p_ba db_a
}

NavState Preintegrator::predict(const NavState& x_i, const model::ImuBias& b,
                                const Eigen::Vector3d& g) const {
  const PreintegratedDelta d = corrected(b);
  const double T = dt_ij_;
  return {x_i.R * d.dR,                                         // R_j = R_i dR
          x_i.v + g * T + x_i.R * d.dv,                         // v_j = v_i + g T + R_i dv
          x_i.p + x_i.v * T + 0.5 * g * T * T + x_i.R * d.dp};  // p_j = ...
}

}  // namespace legkit::imu
