// `legkit study fusion` (section 57.8): proprioception alone against exteroceptive fusion on one
// long run. The physics trot walks a circle (0.5 m/s, a lap of about 100 s), the InEKF with the
// kit's default parameters runs on the recommended contact chain (as `legkit run` does on
// physics) and drifts; simulated SLAM poses (fusion::simulatePoses: 10 Hz, 80 ms late, a slow
// drift, one loop-closure jump, a corridor leaving one axis unobserved) bound it in each of the
// couplings built so far, fed the same inputs row by row:
//   proprio    the InEKF alone (its odom frame is the map frame at the start)
//   loose      map pose = T_MO T_OB, T_MO from fusion::MapOdomAlignment (the odometry untouched)
//   injection  the poses as updates of a second InEKF whose world is the map, each applied at its
//              stamp and the inputs since re-run (fusion::DelayedFilter)
//   smoother   fusion::FixedLagSmoother (Ceres: 2 s window, keyframes every 0.1 s, IMU,
//   leg-odometry,
//              bias-walk and pose factors, the leg-velocity bias)
// Metrics against the truth: ATE, RPE over 10 m, the yaw error at the end, the position error
// through the corridor and around the loop closure. Writes to --out: fusion-trace.csv (10 Hz
// time series), fusion-poses.csv (the simulated poses), summary.json, and the figures of
// tools/plots/57.8-fusion.py.
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>

namespace legkit::tools {

// Adds the subcommand `fusion` to `study`, its options held by the subcommand itself.
CLI::App* addStudyFusion(CLI::App& study);
// Runs the study with the options parsed into `fusion` (the subcommand addStudyFusion made).
// Returns the exit code; throws OutputError when --out cannot be written.
int runStudyFusion(const CLI::App& fusion, std::ostream& out);

}  // namespace legkit::tools
