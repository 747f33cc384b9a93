#include "estimation/fusion/pose_simulator.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace legkit::fusion {
namespace {

void require(bool ok, const char* field, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("PoseSimulatorOptions.") + field + ": expected " +
                                expected);
  }
}

}  // namespace

void checkPoseSimulatorOptions(const PoseSimulatorOptions& o) {
  const auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  const auto non_negative = [](double x) { return std::isfinite(x) && x >= 0.0; };
  require(positive(o.rate), "rate", "a finite rate > 0 [Hz]");
  require(positive(o.latency), "latency", "a finite latency > 0 [s]");
  require(non_negative(o.sigma_position), "sigma_position", "a finite sigma >= 0 [m]");
  require(non_negative(o.sigma_attitude), "sigma_attitude", "a finite sigma >= 0 [rad]");
  require(non_negative(o.drift_position), "drift_position", "a finite density >= 0 [m/sqrt(s)]");
  require(non_negative(o.drift_yaw), "drift_yaw", "a finite density >= 0 [rad/sqrt(s)]");
  require(!std::isnan(o.loop_closure_time), "loop_closure_time", "a time (infinity: never)");
  require(std::isfinite(o.corridor_start), "corridor_start", "a finite time [s]");
  require(std::isfinite(o.corridor_end) && o.corridor_end >= o.corridor_start, "corridor_end",
          "a finite time >= corridor_start [s]");
  require(o.corridor_axis == 0 || o.corridor_axis == 1, "corridor_axis", "0 (x) or 1 (y)");
  require(positive(o.corridor_sigma), "corridor_sigma", "a finite sigma > 0 [m]");
  require(non_negative(o.corridor_drift_rate), "corridor_drift_rate", "a finite rate >= 0 [m/s]");
}

SimulatedPoses simulatePoses(const io::Log& truth, const PoseSimulatorOptions& o,
                             std::uint64_t seed) {
  checkPoseSimulatorOptions(o);
  if (!truth.layout.ground_truth) {
    throw std::invalid_argument("simulatePoses: the log '" + truth.source +
                                "' has no ground truth (gt_ columns)");
  }
  // A floor on the noise: a zero sigma would make the reported covariance singular.
  constexpr double kMinSigma = 1e-9;
  const double sigma_p = std::max(o.sigma_position, kMinSigma);
  const double sigma_r = std::max(o.sigma_attitude, kMinSigma);

  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto gaussian3 = [&] { return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)); };

  SimulatedPoses out;
  if (truth.rows.empty()) return out;
  const double period = 1.0 / o.rate;
  const double t0 = truth.rows.front().t;
  out.poses.reserve(static_cast<std::size_t>((truth.rows.back().t - t0) * o.rate) + 2);
  out.drift.reserve(out.poses.capacity());

  MapDrift drift;
  double last_t = t0;
  bool closed = false;  // the loop closure has happened
  long tick = 0;
  for (const auto& row : truth.rows) {
    // The first row at or after tick k (1 ns of slack for the rounding of 0.01 k and 0.1 k).
    const auto tickTime = [&](long k) { return t0 + k * period - 1e-9; };
    if (row.t < tickTime(tick)) continue;
    while (tickTime(tick) <= row.t) ++tick;
    if (!row.gt_valid) continue;

    // The drift up to this stamp: random walks, the corridor's drift, the loop closure's snap.
    const double dt = row.t - last_t;
    last_t = row.t;
    drift.yaw += o.drift_yaw * std::sqrt(dt) * normal(rng);
    drift.p += o.drift_position * std::sqrt(dt) * gaussian3();
    drift.in_corridor = row.t >= o.corridor_start && row.t < o.corridor_end;
    if (drift.in_corridor) drift.p(o.corridor_axis) += o.corridor_drift_rate * dt;
    if (!closed && row.t >= o.loop_closure_time) {
      closed = true;
      drift.yaw = 0.0;
      drift.p.setZero();
    }

    // The reported covariance of (dtheta, dp), and noise drawn from the nominal one.
    Matrix6d cov = Matrix6d::Zero();
    cov.diagonal() << Eigen::Vector3d::Constant(sigma_r * sigma_r),
        Eigen::Vector3d::Constant(sigma_p * sigma_p);
    const Eigen::Vector3d n_theta = sigma_r * gaussian3();
    const Eigen::Vector3d n_p = sigma_p * gaussian3();
    if (drift.in_corridor)
      cov(3 + o.corridor_axis, 3 + o.corridor_axis) = o.corridor_sigma * o.corridor_sigma;

    // T_MB = D T_WB, then the noise in the map frame.
    const Eigen::Matrix3d R_D = Eigen::AngleAxisd(drift.yaw, Eigen::Vector3d::UnitZ()).matrix();
    const Eigen::Matrix3d R_WB = row.gt_q.normalized().toRotationMatrix();
    PoseMeasurement z;
    z.t = row.t;
    z.t_arrival = row.t + o.latency;
    z.R_MB = lie::SO3d::Exp(n_theta) * lie::SO3d::fromQuaternion(Eigen::Quaterniond(R_D * R_WB));
    z.p_MB = R_D * row.gt_p + drift.p + n_p;
    z.cov = cov;
    out.poses.push_back(z);
    out.drift.push_back(drift);
  }
  return out;
}

}  // namespace legkit::fusion
