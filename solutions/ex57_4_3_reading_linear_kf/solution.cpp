// Reference solution to exercise 57.4.3 (the discussion is in answer.md).
#include <Eigen/Geometry>

#include "ex57_4_3.hpp"

namespace ex57_4_3 {

// B Sigma_u B^T per axis with B = (dt^2/2, dt), Sigma_u = sigma_a^2 / dt.
Eigen::Matrix2d navigationNoisePerAxis(double dt, double accel_density) {
  const double q = accel_density * accel_density;
  Eigen::Matrix2d Q;
  Q << q * dt * dt * dt / 4.0, q * dt * dt / 2.0, q * dt * dt / 2.0, q * dt;
  return Q;
}

// Only the rows and columns of p change: P_pp + dt (P_pv + P_vp) + dt^2 P_vv, P_pj + dt P_vj.
Matrix18 predictCovariance(const Matrix18& P, double dt) {
  Matrix18 out = P;
  const Eigen::Matrix3d P_pv = P.block<3, 3>(0, 3);
  out.block<3, 3>(0, 0) += dt * (P_pv + P_pv.transpose()) + dt * dt * P.block<3, 3>(3, 3);
  out.block<3, 15>(0, 3) += dt * P.block<3, 15>(3, 3);
  out.block<15, 3>(3, 0) = out.block<3, 15>(0, 3).transpose();
  return out;
}

Matrix18 josephUpdate(const Matrix18& P, const Matrix18x3& K, int foot, const Eigen::Matrix3d& Rn) {
  const int d = 6 + 3 * foot;
  const Matrix18x3 N = P.middleCols<3>(d) - P.middleCols<3>(0);  // P H^T
  const Eigen::Matrix3d S = N.middleRows<3>(d) - N.middleRows<3>(0) + Rn;
  const Matrix18x3 V = 0.5 * K * S - N;
  const Matrix18 W = K * V.transpose();
  return P + (W + W.transpose());
}

// mean_i -R (w x r_i + r_dot_i) = -R (w x r_bar + r_dot_bar): linear in (r_i, r_dot_i).
Eigen::Vector3d centroidVelocity(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                                 const std::vector<legkit::ContactMeasurement>& stance) {
  Eigen::Vector3d r_bar = Eigen::Vector3d::Zero(), r_dot_bar = Eigen::Vector3d::Zero();
  for (const legkit::ContactMeasurement& c : stance) {
    r_bar += c.p_body;
    r_dot_bar += *c.v_body;
  }
  const double k = static_cast<double>(stance.size());
  return -R * (w_b.cross(r_bar / k) + r_dot_bar / k);
}

}  // namespace ex57_4_3
