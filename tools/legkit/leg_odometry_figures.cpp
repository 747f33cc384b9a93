// Data for the figure of chapters/57.3-leg-kinematics.md: leg-odometry velocity against the truth
// on the simulator's "turn" scenario (a trot turning in place at 0.5 rad/s).
//
//   build/legkit-leg-odometry-figures OUT.csv
//   /usr/bin/python3 tools/plots/57.3-leg-odometry.py OUT.csv chapters/figures
//
// Columns: t, gt_vx, gt_vy, lo_vx, lo_vy (Go2 sensor noise, mean over stance feet),
// err_right, err_wrong_frame (noiseless: |v - gt_v| with the correct formula and with the body-
// frame foot velocity J qdot used as if it were a world-frame one).
#include <Eigen/Geometry>
#include <array>
#include <cstdio>
#include <exception>
#include <fstream>

#include "estimation/leg_odometry/velocity_fusion.hpp"
#include "sim/simulator.hpp"

namespace {

using legkit::model::QuadrupedKinematics;

struct RowResult {
  bool stance = false;
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_wrong_frame = Eigen::Vector3d::Zero();
};

RowResult legOdometry(const legkit::io::LogRow& row, const QuadrupedKinematics& kin) {
  std::array<legkit::ContactMeasurement, legkit::model::kNumLegs> c;
  std::size_t k = 0;
  RowResult out;
  const Eigen::Matrix3d R = row.gt_q.toRotationMatrix();
  for (int leg = 0; leg < legkit::model::kNumLegs; ++leg) {
    if (!row.contact[leg]) continue;
    const Eigen::Vector3d q = row.q.segment<3>(3 * leg), dq = row.dq.segment<3>(3 * leg);
    c[k] = {leg, kin.footPosition(leg, q), Eigen::Matrix3d::Identity() * 1e-6,
            kin.footJacobian(leg, q) * dq};
    out.v_wrong_frame += -(R * row.gyro.cross(c[k].p_body) + *c[k].v_body);
    ++k;
  }
  if (k == 0) return out;
  out.stance = true;
  out.v = legkit::leg_odometry::meanVelocity(R, row.gyro,
                                             legkit::leg_odometry::ContactSpan(c.data(), k));
  out.v_wrong_frame /= static_cast<double>(k);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.csv\n", argv[0]);
    return 2;
  }
  try {
    const QuadrupedKinematics kin;
    legkit::sim::SimOptions options;
    options.scenario = legkit::sim::scenarioByName("turn");
    options.duration = 8.0;
    options.seed = 573;
    const legkit::io::Log noisy = legkit::sim::simulate(options, kin).log;
    const legkit::io::Log clean = legkit::sim::simulate(options.noiseless(), kin).log;
    std::ofstream out(argv[1]);
    out << "t,gt_vx,gt_vy,lo_vx,lo_vy,err_right,err_wrong_frame\n";
    out.precision(10);
    for (std::size_t i = 0; i < noisy.rows.size(); ++i) {
      const RowResult n = legOdometry(noisy.rows[i], kin), c = legOdometry(clean.rows[i], kin);
      if (!n.stance || !c.stance) continue;
      const Eigen::Vector3d& gt = clean.rows[i].gt_v;
      out << clean.rows[i].t << ',' << gt.x() << ',' << gt.y() << ',' << n.v.x() << ',' << n.v.y()
          << ',' << (c.v - gt).norm() << ',' << (c.v_wrong_frame - gt).norm() << '\n';
    }
    return out ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "legkit-leg-odometry-figures: %s\n", e.what());
    return 1;
  }
}
