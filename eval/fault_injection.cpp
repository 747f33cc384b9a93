#include "eval/fault_injection.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "estimation/contact/foot_force.hpp"

namespace legkit::eval {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void requireJoints(const io::Log& log, const char* fault) {
  if (!log.layout.joints) {
    throw std::invalid_argument(std::string(fault) + ": the log has no quadruped joint columns");
  }
}

void requireForce(const io::Log& log, const char* fault) {
  if (!log.layout.force) {
    throw std::invalid_argument(std::string(fault) + ": the log has no force_<foot> columns");
  }
}

// The median interval between rows: the IMU's nominal period, whatever was dropped.
double nominalPeriod(const io::Log& log) {
  std::vector<double> dt;
  dt.reserve(log.rows.size());
  for (std::size_t k = 1; k < log.rows.size(); ++k) dt.push_back(log.rows[k].t - log.rows[k - 1].t);
  if (dt.empty()) throw std::invalid_argument("runMonitored: the log needs at least two rows");
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  return dt[dt.size() / 2];
}

}  // namespace

io::Log dropImuRows(const io::Log& log, double t0, double duration) {
  io::Log out = log;
  out.rows.clear();
  for (const io::LogRow& row : log.rows) {
    if (!(row.t > t0 && row.t < t0 + duration)) out.rows.push_back(row);
  }
  return out;
}

io::Log freezeEncoder(const io::Log& log, int joint, double t0) {
  requireJoints(log, "freezeEncoder");
  if (joint < 0 || joint >= 3 * io::kNumLegs) {
    throw std::invalid_argument("freezeEncoder: joint " + std::to_string(joint) +
                                " outside [0, 12)");
  }
  io::Log out = log;
  std::optional<double> held;
  for (io::LogRow& row : out.rows) {
    if (row.t < t0) continue;
    if (!held) held = row.q[joint];
    row.q[joint] = *held;
    row.dq[joint] = 0.0;
  }
  return out;
}

io::Log driftForce(const io::Log& log, int foot, double t0, double ramp, double bias) {
  requireForce(log, "driftForce");
  if (foot < 0 || foot >= log.layout.num_feet) {
    throw std::invalid_argument("driftForce: foot " + std::to_string(foot) + " outside [0, " +
                                std::to_string(log.layout.num_feet) + ")");
  }
  if (!(ramp > 0.0)) throw std::invalid_argument("driftForce: ramp must be positive");
  io::Log out = log;
  for (io::LogRow& row : out.rows) {
    if (row.t >= t0) row.force[foot] += bias * std::min(1.0, (row.t - t0) / ramp);
  }
  return out;
}

io::Log silenceForces(const io::Log& log, double t0, double duration) {
  requireForce(log, "silenceForces");
  io::Log out = log;
  for (io::LogRow& row : out.rows) {
    if (row.t >= t0 && row.t < t0 + duration) row.force.fill(0.0);
  }
  return out;
}

io::Log delayEncoders(const io::Log& log, double delay) {
  requireJoints(log, "delayEncoders");
  if (!(delay >= 0.0)) throw std::invalid_argument("delayEncoders: delay must be >= 0");
  io::Log out = log;
  std::size_t j = 0;  // the last source row at or before t_k - delay
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    while (j + 1 < k + 1 && log.rows[j + 1].t <= log.rows[k].t - delay) ++j;
    out.rows[k].q = log.rows[j].q;
    out.rows[k].dq = log.rows[j].dq;
    out.rows[k].tau = log.rows[j].tau;
  }
  return out;
}

io::Log shockAccelerometer(const io::Log& log, double t0, double duration,
                           const Eigen::Vector3d& shock) {
  io::Log out = log;
  for (io::LogRow& row : out.rows) {
    if (row.t >= t0 && row.t < t0 + duration) row.acc += shock;
  }
  return out;
}

double MonitoredRun::maxOver(const std::vector<double>& e, double t0, double t1) const {
  double worst = 0.0;
  for (std::size_t k = 0; k < e.size(); ++k) {
    if (t[k] >= t0 && t[k] <= t1) worst = std::max(worst, e[k]);
  }
  return worst;
}

MonitoredRun runMonitored(Estimator& estimator, const io::Log& log, ContactPipeline& pipeline,
                          const EstimateSample& x0, const MonitoredRunOptions& options) {
  const int num_feet = log.layout.num_feet;
  engineering::HealthMonitor monitor(options.monitor, num_feet, nominalPeriod(log));
  const bool quadruped = log.layout.joints && log.layout.num_joints == 0;
  const bool force_model = quadruped && log.layout.torque && log.layout.force;
  const contact::FootForceFromTorque torque_force(model::QuadrupedGeometry::go2(),
                                                  model::QuadrupedInertia::go2());
  pipeline.reset();
  estimator.reset(x0);

  MonitoredRun out;
  out.detected_at.fill(kNaN);
  const std::size_t n = log.rows.size();
  out.t.reserve(n);
  out.position_error.reserve(n);
  out.velocity_error.reserve(n);
  out.attitude_error.reserve(n);
  out.uncertain.reserve(n);
  out.position_sigma.reserve(n);
  out.velocity_sigma.reserve(n);

  engineering::MonitorInput in;
  in.has_force = log.layout.force;
  in.has_exteroception = options.has_exteroception;
  in.num_joints = quadruped ? 3 * io::kNumLegs : log.layout.num_joints;
  for (std::size_t k = 0; k < n; ++k) {
    io::LogRow row = log.rows[k];
    const double dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
    const EstimateSample x = estimator.estimate();
    const std::optional<BaseCovariance> P = estimator.covariance();

    // What the monitor sees: the raw readings, and the force model on the estimate.
    in.t = row.t;
    in.gyro = row.gyro;
    if (quadruped) {
      in.q.head<12>() = row.q;
      in.dq.head<12>() = row.dq;
    } else {
      in.q = row.joint_q;
      in.dq = row.joint_dq;
    }
    in.force = row.force;
    in.force_model.fill(kNaN);
    if (force_model) {
      const contact::BaseFeedback base = contact::feedbackFrom(x);
      const auto f = torque_force.estimate(pipeline.frontend().signals(row, dt, base));
      for (int i = 0; i < io::kNumLegs; ++i) in.force_model[i] = f[i].z();
    }
    if (options.has_exteroception) {
      const double last =
          std::floor(std::min(row.t, options.exteroception_until) * options.exteroception_rate) /
          options.exteroception_rate;
      in.exteroception_t =
          last >= log.rows.front().t ? last : -std::numeric_limits<double>::infinity();
    }

    // The answers, from the monitor's last update.
    if (options.degrade && log.layout.force) {
      for (int i = 0; i < num_feet; ++i) {
        if (monitor.forceNoiseScale(i) > 1.0) {
          row.force[i] = kNaN;
          ++out.forces_distrusted;
        }
      }
    }
    StepInput input = pipeline.step(row, dt, x, P);
    if (options.degrade) out.contacts_removed += monitor.applyTo(input);
    estimator.step(input);

    const EstimateSample e = estimator.estimate();
    const std::optional<BaseCovariance> P_after = estimator.covariance();
    in.v_hat = e.v;
    in.P = P_after ? &*P_after : nullptr;
    in.health = &estimator.health();
    const engineering::MonitorReport& r = monitor.update(in);
    for (int i = 0; i < num_feet; ++i) {
      out.max_force_bias[i] = std::max(out.max_force_bias[i], std::abs(monitor.forceBias(i)));
    }
    for (int a = 0; a < engineering::kNumAlarms; ++a) {
      if (r.active[a] && std::isnan(out.detected_at[a])) out.detected_at[a] = row.t;
    }

    out.finite = out.finite && e.p.allFinite() && e.v.allFinite() && e.q.coeffs().allFinite() &&
                 (!P_after || P_after->P.allFinite());
    out.t.push_back(row.t);
    out.position_error.push_back((e.p - row.gt_p).norm());
    out.velocity_error.push_back((e.v - row.gt_v).norm());
    out.attitude_error.push_back(row.gt_q.angularDistance(e.q));
    out.uncertain.push_back(r.uncertain);
    out.position_sigma.push_back(r.position_sigma);
    out.velocity_sigma.push_back(r.velocity_sigma);
  }
  out.report = monitor.report();
  out.health = estimator.health();
  for (int f = 0; f < static_cast<int>(Fault::kCount); ++f) {
    out.health.count[f] += pipeline.health().count[f];
  }
  return out;
}

}  // namespace legkit::eval
