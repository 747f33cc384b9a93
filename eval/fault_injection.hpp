// Fault injection (section 57.9): a sensor fault written into a copy of a log, and a run of an
// estimator on detected contacts with the health monitor (estimation/engineering/monitors.hpp)
// watching it and, when asked, the monitor's answers applied. The fault-injection tests and the
// troubleshooting table's runs (chapters/57.9) are made of these.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "estimation/contact_pipeline.hpp"
#include "estimation/engineering/monitors.hpp"
#include "estimation/estimator.hpp"
#include "io/log.hpp"

namespace legkit::eval {

// Each returns a copy of `log` with one fault; the other columns are untouched. Times are log
// times [s]. Throw std::invalid_argument for an index outside the log's joints or feet, or a
// layout without the column the fault needs.

// The IMU samples in (t0, t0 + duration) never arrive: those rows are removed.
io::Log dropImuRows(const io::Log& log, double t0, double duration);
// From t0 on, quadruped joint `joint` (3 leg + j) reads its angle at t0 and a rate of 0.
io::Log freezeEncoder(const io::Log& log, int joint, double t0);
// From t0 on, foot `foot`'s force sensor reads `bias` [N] more, reached linearly over `ramp` [s].
io::Log driftForce(const io::Log& log, int foot, double t0, double ramp, double bias);
// In [t0, t0 + duration) every force sensor reads 0 N: the foot-sensor detector finds no foot
// down (as a threshold set too high would), the filters dead-reckon.
io::Log silenceForces(const io::Log& log, double t0, double duration);
// The joint encoders (q, dq, tau) read `delay` [s] late against the IMU: row k carries the joint
// values of the last row at or before t_k - delay (the first row's before that).
io::Log delayEncoders(const io::Log& log, double delay);
// In [t0, t0 + duration) the accelerometer reads `shock` [m/s^2] (body frame) more: an impact.
io::Log shockAccelerometer(const io::Log& log, double t0, double duration,
                           const Eigen::Vector3d& shock);

struct MonitoredRunOptions {
  engineering::MonitorParams monitor;
  // Apply the monitor's answers: the contacts of an untrusted leg removed from the filter's input
  // (HealthMonitor::applyTo), and a drifting force sensor not trusted (forceNoiseScale > 1: its
  // reading is replaced by NaN, so that the fallback chain hands that foot to its next detector).
  bool degrade = true;
  // Synthetic exteroception (57.8 has none yet): updates at `exteroception_rate` until
  // `exteroception_until` [s]; none when has_exteroception is false.
  bool has_exteroception = false;
  double exteroception_rate = 10.0;  // [Hz]
  double exteroception_until = std::numeric_limits<double>::infinity();
};

struct MonitoredRun {
  // Per row: time, error against the log's truth (position [m], world velocity [m/s], attitude
  // angle [rad]) and whether the monitor said the estimate is uncertain.
  std::vector<double> t, position_error, velocity_error, attitude_error;
  // Per row, the monitor's largest position and velocity sigma of P (0 without a covariance).
  std::vector<double> position_sigma, velocity_sigma;
  std::vector<bool> uncertain;
  // Per alarm: the row time at which it was first raised (NaN: never), and the monitor's record
  // at the end of the run.
  std::array<double, engineering::kNumAlarms> detected_at{};
  engineering::MonitorReport report;
  Health health;                        // the estimator's and the pipeline's
  std::uint64_t contacts_removed = 0;   // by the stuck-encoder answer
  std::uint64_t forces_distrusted = 0;  // rows x feet whose force reading was not trusted
  bool finite = true;                   // every estimate and covariance was finite
  // Per foot, the largest |windowed mean (sensor - model) force| the monitor saw [N].
  std::array<double, io::kMaxFeet> max_force_bias{};

  // The largest error of `e` (one of the vectors above) over rows with t in [t0, t1].
  double maxOver(const std::vector<double>& e, double t0, double t1) const;
  double detectedAt(engineering::Alarm a) const { return detected_at[static_cast<int>(a)]; }
};

// Runs `estimator` from x0 over the log on `pipeline`'s contacts with a HealthMonitor at the
// log's nominal period (the median row interval). The monitor's force model is the force from
// the joint torques (contact/foot_force.hpp, the Go2's model) where the log has the quadruped's
// joints and torques, else none. The pipeline and the estimator are reset first. Throws what the
// pipeline or the estimator throws.
MonitoredRun runMonitored(Estimator& estimator, const io::Log& log, ContactPipeline& pipeline,
                          const EstimateSample& x0, const MonitoredRunOptions& options);

}  // namespace legkit::eval
