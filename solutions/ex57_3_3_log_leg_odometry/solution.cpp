// Reference solution to exercise 57.3.3, built on the kit's kinematics and leg odometry.
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <stdexcept>

#include "estimation/leg_odometry/velocity_fusion.hpp"
#include "ex57_3_3.hpp"
#include "io/log_reader.hpp"

namespace ex57_3_3 {

std::optional<Eigen::Vector3d> rowVelocity(const legkit::io::LogRow& row,
                                           const legkit::model::QuadrupedKinematics& kin) {
  std::array<legkit::ContactMeasurement, legkit::model::kNumLegs> stance;
  std::size_t k = 0;
  for (int leg = 0; leg < legkit::model::kNumLegs; ++leg) {
    if (!row.contact[leg]) continue;
    const Eigen::Vector3d q = row.q.segment<3>(3 * leg), dq = row.dq.segment<3>(3 * leg);
    legkit::ContactMeasurement& c = stance[k++];
    c.foot = leg;
    c.p_body = kin.footPosition(leg, q);         // r_i = FK(q_i)
    c.cov = Eigen::Matrix3d::Identity() * 1e-6;  // not used by the plain mean
    c.v_body = kin.footJacobian(leg, q) * dq;    // J_i dq_i
  }
  if (k == 0) return std::nullopt;
  const Eigen::Matrix3d R = row.gt_q.normalized().toRotationMatrix();
  return legkit::leg_odometry::meanVelocity(R, row.gyro,
                                            legkit::leg_odometry::ContactSpan(stance.data(), k));
}

Comparison compareWithTruth(const legkit::io::Log& log,
                            const legkit::model::QuadrupedKinematics& kin) {
  if (!log.layout.joints || !log.layout.contact || !log.layout.ground_truth) {
    throw std::invalid_argument(
        "compareWithTruth: the log needs joint, contact and ground-truth columns");
  }
  Comparison out;
  double sum_sq = 0.0;
  for (const legkit::io::LogRow& row : log.rows) {
    const std::optional<Eigen::Vector3d> v = rowVelocity(row, kin);
    if (!v) {
      ++out.rows_without_contact;
      continue;
    }
    const double e = (*v - row.gt_v).norm();
    sum_sq += e * e;
    out.max_error = std::max(out.max_error, e);
    ++out.rows_used;
  }
  if (out.rows_used > 0) out.rmse = std::sqrt(sum_sq / out.rows_used);
  return out;
}

Comparison compareLogFile(const std::string& path, const legkit::model::QuadrupedKinematics& kin) {
  return compareWithTruth(legkit::io::readLog(path), kin);
}

}  // namespace ex57_3_3
