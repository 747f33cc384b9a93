// A porter's first hour: the estimator manager (estimation/state_estimator.hpp) of an installed
// legkit, built from a settings file, fed a log row by row as a control loop would feed it.
//   estimate SETTINGS.yaml LOG.csv   prints the final state and, with truth, its position error
#include <cmath>
#include <cstdio>
#include <exception>

#include "estimation/settings.hpp"
#include "estimation/state_estimator.hpp"
#include "io/log_reader.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: estimate SETTINGS.yaml LOG.csv\n");
    return 1;
  }
  try {
    using namespace legkit;
    const Settings settings = loadSettings(argv[1]);
    const io::Log log = io::readLog(argv[2]);
    StateEstimator manager(settings);
    ImuSample imu;
    JointSample joints;
    ForceSample forces;
    forces.valid = log.layout.force;
    EstimateSample x;
    for (const io::LogRow& row : log.rows) {
      imu = {row.t, row.gyro, row.acc};
      joints.q.head<io::kNumJoints>() = row.q;
      joints.dq.head<io::kNumJoints>() = row.dq;
      for (int f = 0; f < io::kNumLegs; ++f) forces.force[f] = row.force[f];
      x = manager.update(imu, joints, forces).x;
    }
    std::printf("t %.3f  p %.4f %.4f %.4f\n", x.t, x.p.x(), x.p.y(), x.p.z());
    if (log.layout.ground_truth) {
      // The manager starts at the origin, the truth where the simulator put the robot.
      const Eigen::Vector3d walked = log.rows.back().gt_p - log.rows.front().gt_p;
      const double error = (x.p - walked).head<2>().norm();
      std::printf("walked %.3f m, horizontal error %.4f m\n", walked.norm(), error);
      if (!std::isfinite(error) || error > 0.1 * walked.norm() + 0.05) return 3;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "estimate: %s\n", e.what());
    return 2;
  }
}
