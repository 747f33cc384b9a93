// Reference solution to exercise 57.8.2 (the code part; the discussion is answer.md).
#include <Eigen/LU>
#include <stdexcept>

#include "ex57_8_2.hpp"

namespace ex57_8_2 {

LegDelta preintegrate(const std::vector<LegSample>& samples, const Eigen::Vector3d& b_v) {
  LegDelta d;
  d.b_v_lin = b_v;
  for (const LegSample& s : samples) {
    const Eigen::Matrix3d dR_ik = d.dR.matrix();
    d.dp += dR_ik * (s.v - b_v) * s.dt;  // dp_ij += dR_ik (v_k - b_v) dt_k
    d.dp_db_v -= dR_ik * s.dt;           // d(dp_ij)/d(b_v) -= dR_ik dt_k
    d.dR = d.dR * lie::SO3d::Exp(s.omega * s.dt);
  }
  return d;
}

// Exact, not only first order: dp_ij is linear in b_v (dR_ik does not depend on it).
Eigen::Vector3d correctedDelta(const LegDelta& d, const Eigen::Vector3d& b_v) {
  return d.dp + d.dp_db_v * (b_v - d.b_v_lin);
}

// R_i^T (p_j - p_i) = dp + dp_db_v (b_v - b_v_lin)  =>  b_v = b_v_lin + dp_db_v^-1 (... - dp).
Eigen::Vector3d velocityBiasFromPoses(const LegDelta& d, const lie::SO3d& R_i,
                                      const Eigen::Vector3d& p_i, const Eigen::Vector3d& p_j) {
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(d.dp_db_v);
  if (!lu.isInvertible())
    throw std::invalid_argument(
        "velocityBiasFromPoses: d(dp)/d(b_v) is singular (no time "
        "between the keyframes)");
  return d.b_v_lin + lu.solve(R_i.matrix().transpose() * (p_j - p_i) - d.dp);
}

}  // namespace ex57_8_2
