// Simulated exteroceptive poses (section 57.8): what a SLAM system would report about the base of
// a simulated run, made from the run's ground truth (io::Log's gt_ columns).
//
// Model. Each pose describes the truth T_WB at a stamp t (a truth row, the first at or after each
// 1/rate tick), seen through a slowly drifting map frame and white noise:
//   T_MB,nf = D(t) T_WB,        D = (Rz(psi), d)            the map's drift (psi yaw [rad], d [m])
//   R_MB = Exp(n_theta) R_MB,nf,  p_MB = p_MB,nf + n_p,   (n_theta, n_p) ~ N(0, C(t))
// so a pose's error is (n_theta, n_p) in the kit's (dtheta, dp) map-frame convention, and cov is
// C(t), the covariance the noise is drawn from (the reader's convention, pose_measurement.hpp).
//  - drift: psi and d are random walks (densities drift_yaw, drift_position, from 0 at the first
//    pose); the true map-to-world transform is D (the world W of the truth is the map's origin).
//  - loop closure: at the first pose at or after loop_closure_time the drift is snapped back to
//    zero (psi = 0, d = 0): the poses jump by the drift accumulated so far, then drift afresh.
//  - corridor: for stamps in [corridor_start, corridor_end) the map axis corridor_axis (0: x, 1: y)
//    is unobserved: its reported standard deviation is corridor_sigma and d along it grows at
//    corridor_drift_rate [m/s] (the value drifts; the drift stays until the loop closure snaps it).
//    The white noise drawn keeps the nominal sigma_position: the reported variance is an honest
//    upper bound there, not the noise's own.
//  - latency: t_arrival = t + latency.
//  - a truth row flagged gt_valid = 0 gives no pose (the tick is skipped).
// Everything is a function of (truth, options, seed): the same inputs give the same poses.
#pragma once

#include <cstdint>
#include <vector>

#include "estimation/fusion/pose_measurement.hpp"
#include "io/log.hpp"

namespace legkit::fusion {

struct PoseSimulatorOptions {
  double rate = 10.0;                 // poses per second [Hz]
  double latency = 0.08;              // t_arrival - t [s]
  double sigma_position = 0.02;       // white noise per map axis [m]
  double sigma_attitude = 0.005;      // white noise per map axis [rad]
  double drift_position = 0.005;      // random-walk density of d, per axis [m/sqrt(s)]
  double drift_yaw = 0.0005;          // random-walk density of psi [rad/sqrt(s)]
  double loop_closure_time = 200.0;   // [s] the drift snaps back to zero (infinity: never)
  double corridor_start = 120.0;      // [s] start of the degenerate stretch
  double corridor_end = 150.0;        // [s] its end (corridor_start == corridor_end: none)
  int corridor_axis = 0;              // the unobserved horizontal map axis: 0 (x) or 1 (y)
  double corridor_sigma = 5.0;        // reported standard deviation on that axis [m]
  double corridor_drift_rate = 0.05;  // how fast the value along it drifts [m/s]
};

// Throws std::invalid_argument naming the field: rate, latency <= 0 or non-finite, a negative or
// non-finite sigma or drift, corridor_end < corridor_start, corridor_axis not 0 or 1,
// corridor_sigma <= 0, a NaN loop_closure_time.
void checkPoseSimulatorOptions(const PoseSimulatorOptions& options);

// The map's drift at one pose: T_MB,nf = D T_WB with D = (Rz(yaw), p).
struct MapDrift {
  double yaw = 0.0;                             // [rad]
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  // [m]
  bool in_corridor = false;                     // the pose's stamp is in the corridor
};

struct SimulatedPoses {
  std::vector<PoseMeasurement> poses;
  std::vector<MapDrift> drift;  // one per pose: the truth the poses' errors are measured from
};

// Throws std::invalid_argument if the log has no ground truth or the options are bad.
SimulatedPoses simulatePoses(const io::Log& truth, const PoseSimulatorOptions& options,
                             std::uint64_t seed);

}  // namespace legkit::fusion
