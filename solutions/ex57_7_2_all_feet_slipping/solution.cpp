// Reference solution of exercise 57.7.2.
#include <stdexcept>

#include "ex57_7_2.hpp"
#include "model/imu_model.hpp"

namespace ex57_7_2 {

std::vector<Comparison> legsVersusImu(const legkit::io::Log& log, double t_anchor,
                                      const legkit::model::QuadrupedKinematics& kin) {
  if (!log.layout.joints || !log.layout.contact || !log.layout.ground_truth)
    throw std::invalid_argument("legsVersusImu: the log needs joints, contact flags and truth");
  std::size_t k = 0;
  while (k < log.rows.size() && log.rows[k].t < t_anchor) ++k;
  if (k == log.rows.size()) throw std::invalid_argument("legsVersusImu: no row after the anchor");
  std::vector<Comparison> out;
  out.reserve(log.rows.size() - k);
  Eigen::Vector3d v_imu = log.rows[k].gt_v;
  for (; k < log.rows.size(); ++k) {
    const legkit::io::LogRow& row = log.rows[k];
    const Eigen::Matrix3d R = row.gt_q.toRotationMatrix();
    Comparison c;
    c.t = row.t;
    c.v_imu = v_imu;
    // Each stance foot's base velocity, v_i = -R (w x r_i + J_i dq_i).
    Eigen::Vector3d v[legkit::io::kNumLegs];
    int n = 0;
    for (int leg = 0; leg < legkit::io::kNumLegs; ++leg) {
      if (!row.contact[leg]) continue;
      const Eigen::Vector3d q = row.q.segment<3>(3 * leg), dq = row.dq.segment<3>(3 * leg);
      const Eigen::Vector3d r = kin.footPosition(leg, q);
      v[n++] = -R * (row.gyro.cross(r) + kin.footJacobian(leg, q) * dq);
    }
    for (int i = 0; i < n; ++i) {
      c.v_legs += v[i] / n;
      for (int j = i + 1; j < n; ++j) c.spread = std::max(c.spread, (v[i] - v[j]).norm());
    }
    out.push_back(c);
    // The IMU over the interval to the next row: the world acceleration R a_m + g, held.
    if (k + 1 < log.rows.size())
      v_imu += (R * row.acc + legkit::model::gravity()) * (log.rows[k + 1].t - row.t);
  }
  return out;
}

}  // namespace ex57_7_2
