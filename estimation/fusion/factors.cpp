#include "estimation/fusion/factors.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "lie/so3.hpp"

namespace legkit::fusion {

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// S = L^-1 for Sigma = L L^T, so that S^T S = Sigma^-1. Throws unless Sigma is finite, symmetric
// and positive definite.
template <int N>
Eigen::Matrix<double, N, N> whitening(const Eigen::Matrix<double, N, N>& Sigma, const char* where) {
  using MatrixN = Eigen::Matrix<double, N, N>;
  const double scale = Sigma.cwiseAbs().maxCoeff();
  if (!Sigma.allFinite() || !((Sigma - Sigma.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale)) {
    std::ostringstream os;
    os << where << ": covariance must be finite and symmetric, got\n" << Sigma;
    throw std::invalid_argument(os.str());
  }
  const Eigen::LLT<MatrixN> llt(Sigma);
  if (llt.info() != Eigen::Success) {  // a pivot <= 0: not positive definite
    std::ostringstream os;
    os << where << ": covariance must be positive definite, got\n" << Sigma;
    throw std::invalid_argument(os.str());
  }
  MatrixN S = MatrixN::Identity();
  llt.matrixL().solveInPlace(S);
  return S;
}

Eigen::Map<const Matrix3d> rotation(const double* R) {
  return Eigen::Map<const Matrix3d>(R);
}
Eigen::Map<const Vector3d> vec3(const double* x) {
  return Eigen::Map<const Vector3d>(x);
}

// Writes the whitened tangent Jacobian S J_t of a rotation block as its ambient Jacobian.
template <typename Derived>
void setRotationJacobian(double* out, const Eigen::MatrixBase<Derived>& SJ_t, const Matrix3d& R) {
  constexpr int kRows = Derived::RowsAtCompileTime;
  Eigen::Map<Eigen::Matrix<double, kRows, 9, Eigen::RowMajor>> J_a(out);
  J_a = ambientJacobian(SJ_t, R);
}

// Writes a whitened Euclidean 3-column block (Ceres's Jacobians are row-major).
template <typename Derived>
void setJacobian(double* out, const Eigen::MatrixBase<Derived>& SJ) {
  constexpr int kRows = Derived::RowsAtCompileTime;
  Eigen::Map<Eigen::Matrix<double, kRows, 3, Eigen::RowMajor>> J(out);
  J = SJ;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
ImuFactor::ImuFactor(const imu::Preintegrator& pim, const Eigen::Vector3d& g)
    : pim_(pim), g_(g), S_(whitening<9>(pim.covariance(), "ImuFactor")) {
  if (!g.allFinite()) throw std::invalid_argument("ImuFactor: gravity g has a NaN or inf entry");
}

bool ImuFactor::Evaluate(double const* const* parameters, double* residuals,
                         double** jacobians) const {
  const Matrix3d R_i = rotation(parameters[0]);
  const Vector3d v_i = vec3(parameters[1]), p_i = vec3(parameters[2]);
  const Matrix3d R_j = rotation(parameters[3]);
  const Vector3d v_j = vec3(parameters[4]), p_j = vec3(parameters[5]);
  const Vector3d db_g = vec3(parameters[6]) - pim_.linearisationBias().b_g;
  const Vector3d db_a = vec3(parameters[7]) - pim_.linearisationBias().b_a;
  const double T = pim_.dt_ij();

  // Bias-corrected increments (Forster eq. 44).
  const Vector3d phi_bg = pim_.J_R_bg() * db_g;
  const Matrix3d dR = pim_.dR().matrix() * lie::SO3d::Exp(phi_bg).matrix();
  const Vector3d dv = pim_.dv() + pim_.J_v_bg() * db_g + pim_.J_v_ba() * db_a;
  const Vector3d dp = pim_.dp() + pim_.J_p_bg() * db_g + pim_.J_p_ba() * db_a;

  const Matrix3d E = dR.transpose() * R_i.transpose() * R_j;  // Exp(r_phi)
  const Vector3d r_phi = lie::SO3d::logOfMatrix(E);
  const Vector3d u_v = R_i.transpose() * (v_j - v_i - g_ * T);
  const Vector3d u_p = R_i.transpose() * (p_j - p_i - v_i * T - 0.5 * g_ * T * T);
  Eigen::Matrix<double, 9, 1> r;
  r << r_phi, u_v - dv, u_p - dp;
  Eigen::Map<Eigen::Matrix<double, 9, 1>> r_w(residuals);
  r_w = S_ * r;
  if (!jacobians) return true;

  using Block = Eigen::Matrix<double, 9, 3>;
  const Matrix3d JrInv = lie::SO3d::JrInv(r_phi);
  const Matrix3d Rit = R_i.transpose();
  if (jacobians[0]) {  // R_i <- R_i Exp(delta)
    Block J = Block::Zero();
    J.block<3, 3>(0, 0) = -JrInv * R_j.transpose() * R_i;
    J.block<3, 3>(3, 0) = lie::hat3(u_v);
    J.block<3, 3>(6, 0) = lie::hat3(u_p);
    setRotationJacobian(jacobians[0], S_ * J, R_i);
  }
  if (jacobians[1]) {  // v_i
    Block J = Block::Zero();
    J.block<3, 3>(3, 0) = -Rit;
    J.block<3, 3>(6, 0) = -Rit * T;
    setJacobian(jacobians[1], S_ * J);
  }
  if (jacobians[2]) {  // p_i
    Block J = Block::Zero();
    J.block<3, 3>(6, 0) = -Rit;
    setJacobian(jacobians[2], S_ * J);
  }
  if (jacobians[3]) {  // R_j <- R_j Exp(delta)
    Block J = Block::Zero();
    J.block<3, 3>(0, 0) = JrInv;
    setRotationJacobian(jacobians[3], S_ * J, R_j);
  }
  if (jacobians[4]) {  // v_j
    Block J = Block::Zero();
    J.block<3, 3>(3, 0) = Rit;
    setJacobian(jacobians[4], S_ * J);
  }
  if (jacobians[5]) {  // p_j
    Block J = Block::Zero();
    J.block<3, 3>(6, 0) = Rit;
    setJacobian(jacobians[5], S_ * J);
  }
  if (jacobians[6]) {  // b_g: Exp(J (db + e)) = Exp(J db) Exp(Jr(J db) J e)
    Block J = Block::Zero();
    J.block<3, 3>(0, 0) = -JrInv * E.transpose() * lie::SO3d::Jr(phi_bg) * pim_.J_R_bg();
    J.block<3, 3>(3, 0) = -pim_.J_v_bg();
    J.block<3, 3>(6, 0) = -pim_.J_p_bg();
    setJacobian(jacobians[6], S_ * J);
  }
  if (jacobians[7]) {  // b_a
    Block J = Block::Zero();
    J.block<3, 3>(3, 0) = -pim_.J_v_ba();
    J.block<3, 3>(6, 0) = -pim_.J_p_ba();
    setJacobian(jacobians[7], S_ * J);
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
LegOdometryFactor::LegOdometryFactor(const LegPreintegrator& lpi)
    : lpi_(lpi), S_(whitening<3>(lpi.covariance(), "LegOdometryFactor")) {}

bool LegOdometryFactor::Evaluate(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  const Matrix3d R_i = rotation(parameters[0]);
  const Vector3d p_i = vec3(parameters[1]), p_j = vec3(parameters[2]);
  const Vector3d b_v = vec3(parameters[3]), b_g = vec3(parameters[4]);
  const Vector3d u = R_i.transpose() * (p_j - p_i);  // R_i^T (p_j - p_i)
  Eigen::Map<Vector3d> r_w(residuals);
  r_w = S_ * (u - lpi_.corrected(b_v, b_g));
  if (!jacobians) return true;
  if (jacobians[0]) setRotationJacobian(jacobians[0], S_ * lie::hat3(u), R_i);
  if (jacobians[1]) setJacobian(jacobians[1], -S_ * R_i.transpose());
  if (jacobians[2]) setJacobian(jacobians[2], S_ * R_i.transpose());
  if (jacobians[3]) setJacobian(jacobians[3], -S_ * lpi_.J_p_bv());
  if (jacobians[4]) setJacobian(jacobians[4], -S_ * lpi_.J_p_bg());
  return true;
}

// ---------------------------------------------------------------------------------------------
PoseFactor::PoseFactor(const PoseMeasurement& z)
    : R_meas_(z.R_MB.matrix()), p_meas_(z.p_MB), S_(whitening<6>(z.cov, "PoseFactor")) {
  if (!z.valid) throw std::invalid_argument("PoseFactor: the pose is flagged invalid");
  if (!R_meas_.allFinite() || !p_meas_.allFinite()) {
    throw std::invalid_argument("PoseFactor: the pose has a NaN or inf entry");
  }
}

bool PoseFactor::Evaluate(double const* const* parameters, double* residuals,
                          double** jacobians) const {
  const Matrix3d R = rotation(parameters[0]);
  const Vector3d p = vec3(parameters[1]);
  const Vector3d r_theta = lie::SO3d::logOfMatrix(R_meas_ * R.transpose());
  Eigen::Matrix<double, 6, 1> r;
  r << r_theta, p_meas_ - p;
  Eigen::Map<Eigen::Matrix<double, 6, 1>> r_w(residuals);
  r_w = S_ * r;
  if (!jacobians) return true;
  using Block = Eigen::Matrix<double, 6, 3>;
  if (jacobians[0]) {  // Log(Exp(r) Exp(-R delta)) = r - Jr^-1(r) R delta
    Block J = Block::Zero();
    J.block<3, 3>(0, 0) = -lie::SO3d::JrInv(r_theta) * R;
    setRotationJacobian(jacobians[0], S_ * J, R);
  }
  if (jacobians[1]) {
    Block J = Block::Zero();
    J.block<3, 3>(3, 0) = -Matrix3d::Identity();
    setJacobian(jacobians[1], S_ * J);
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
BiasWalkFactor::BiasWalkFactor(double sigma_walk, double dt) {
  if (!(sigma_walk > 0.0) || !std::isfinite(sigma_walk) || !(dt > 0.0) || !std::isfinite(dt)) {
    std::ostringstream os;
    os << "BiasWalkFactor: sigma_walk and dt must be positive and finite, got sigma_walk = "
       << sigma_walk << ", dt = " << dt;
    throw std::invalid_argument(os.str());
  }
  inv_sigma_ = 1.0 / (sigma_walk * std::sqrt(dt));
}

bool BiasWalkFactor::Evaluate(double const* const* parameters, double* residuals,
                              double** jacobians) const {
  Eigen::Map<Vector3d> r_w(residuals);
  r_w = inv_sigma_ * (vec3(parameters[1]) - vec3(parameters[0]));
  if (!jacobians) return true;
  if (jacobians[0]) setJacobian(jacobians[0], -inv_sigma_ * Matrix3d::Identity());
  if (jacobians[1]) setJacobian(jacobians[1], inv_sigma_ * Matrix3d::Identity());
  return true;
}

}  // namespace legkit::fusion
