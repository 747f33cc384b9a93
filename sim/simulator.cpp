#include "sim/simulator.hpp"

#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "sim/quadruped_motion.hpp"

namespace legkit::sim {
namespace {

// Independent generator for one purpose (stream) from the user's seed.
std::mt19937_64 stream(unsigned seed, unsigned id) {
  std::seed_seq seq{seed, id, 0x6c65676bu};  // "legk"
  return std::mt19937_64(seq);
}

void checkOptions(const SimOptions& o) {
  const auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  if (!positive(o.duration)) throw std::invalid_argument("simulate: duration must be > 0");
  if (!positive(o.rate)) throw std::invalid_argument("simulate: rate must be > 0");
  if (!positive(o.mass)) throw std::invalid_argument("simulate: mass must be > 0");
  if (!(o.encoder_angle_sigma >= 0.0) || !(o.encoder_rate_sigma >= 0.0) ||
      !(o.foot_position_sigma >= 0.0)) {
    throw std::invalid_argument("simulate: noise standard deviations must be >= 0");
  }
  if (!(o.faults.dropout_probability >= 0.0 && o.faults.dropout_probability < 1.0)) {
    throw std::invalid_argument("simulate: dropout probability must be in [0, 1)");
  }
  if (!std::isfinite(o.faults.contact_offset)) {
    throw std::invalid_argument("simulate: contact offset must be finite");
  }
}

bool inDropout(const Faults& faults, double t) {
  for (const Dropout& d : faults.dropouts) {
    if (t >= d.start && t < d.start + d.duration) return true;
  }
  return false;
}

// Each stance foot's share of the force m (a - g) that accelerates the base (world frame).
std::array<Eigen::Vector3d, model::kNumLegs> forceShares(
    double mass, const Eigen::Vector3d& a, const std::array<bool, model::kNumLegs>& contact) {
  int n = 0;
  for (bool c : contact) n += c ? 1 : 0;
  std::array<Eigen::Vector3d, model::kNumLegs> f;
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    f[leg] = (contact[leg] && n > 0) ? Eigen::Vector3d(mass * (a - model::gravity()) / n)
                                     : Eigen::Vector3d::Zero();
  }
  return f;
}

}  // namespace

SimOptions& SimOptions::noiseless() {
  imu_noise = model::ImuNoise{0.0, 0.0, 0.0, 0.0};
  initial_bias = model::ImuBias{};
  encoder_angle_sigma = 0.0;
  encoder_rate_sigma = 0.0;
  return *this;
}

SimResult simulate(const SimOptions& options, const model::QuadrupedKinematics& kinematics) {
  checkOptions(options);
  const QuadrupedMotion motion(options.scenario, kinematics, options.faults.slip);
  std::mt19937_64 imu_rng = stream(options.seed, 1);
  std::mt19937_64 encoder_rng = stream(options.seed, 2);
  std::mt19937_64 dropout_rng = stream(options.seed, 3);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);

  SimResult out;
  io::Log& log = out.log;
  // One leg description per log (io/log_reader.hpp): the joints, or the feet they give.
  log.layout.joints = options.foot_columns == io::FootCovariance::kNone;
  log.layout.torque = options.torque && log.layout.joints;
  log.layout.force = options.force;
  log.layout.contact = options.contact;
  log.layout.ground_truth = options.ground_truth;
  log.layout.foot_columns = options.foot_columns;
  std::ostringstream about;
  about.precision(17);
  about << "legkit sim: scenario " << options.scenario.name << ", duration " << options.duration
        << " s, rate " << options.rate << " Hz, seed " << options.seed;
  log.comments.push_back(about.str());

  const double dt = 1.0 / options.rate;
  const long n = std::lround(options.duration * options.rate);
  log.rows.reserve(n);
  out.bias.reserve(n);
  model::ImuBias bias = options.initial_bias;
  for (long k = 0; k < n; ++k) {
    const double t = k * dt;
    const BaseState base = motion.base(t);
    // The IMU reading uses the bias of this sample, then the bias takes its random-walk step;
    // every sample is drawn (and the bias moves) even if a dropout hides it.
    const model::ImuBias bias_now = bias;
    const model::ImuReading imu =
        model::synthesiseReading(options.imu_noise, dt, base.R, base.a, base.w, bias, imu_rng);
    io::LogRow row;
    row.t = t;
    row.gyro = imu.w_m;
    row.acc = imu.a_m;
    std::array<bool, model::kNumLegs> contact{};
    std::array<JointState, model::kNumLegs> joints;
    for (int leg = 0; leg < model::kNumLegs; ++leg) {
      const FootState foot = motion.foot(leg, t);
      contact[leg] = foot.contact;
      joints[leg] = motion.joints(leg, base, foot);
    }
    const auto shares = forceShares(options.mass, base.a, contact);
    for (int leg = 0; leg < model::kNumLegs; ++leg) {
      const JointState& j = joints[leg];
      for (int i = 0; i < 3; ++i) {
        const int index = io::kJointsPerLeg * leg + i;
        row.q(index) = j.q(i) + options.encoder_angle_sigma * unit(encoder_rng);
        row.dq(index) = j.dq(i) + options.encoder_rate_sigma * unit(encoder_rng);
      }
      // Static torque that holds this leg's share of the force: tau = -J^T R^T f.
      row.tau.segment<3>(io::kJointsPerLeg * leg) =
          -kinematics.footJacobian(leg, j.q).transpose() * (base.R.transpose() * shares[leg]);
      row.force[leg] = std::max(shares[leg].z(), 0.0);
      const double t_flag = t - options.faults.contact_offset;
      row.contact[leg] =
          options.faults.contact_offset == 0.0 ? contact[leg] : motion.foot(leg, t_flag).contact;
    }
    if (options.foot_columns != io::FootCovariance::kNone) {
      for (int leg = 0; leg < model::kNumLegs; ++leg) {
        const Eigen::Vector3d q = row.q.segment<3>(io::kJointsPerLeg * leg);
        const Eigen::Matrix3d J = kinematics.footJacobian(leg, q);
        io::FootKinematics& foot = row.feet[leg];
        foot.p_body = kinematics.footPosition(leg, q);
        foot.cov =
            options.encoder_angle_sigma * options.encoder_angle_sigma * J * J.transpose() +
            options.foot_position_sigma * options.foot_position_sigma * Eigen::Matrix3d::Identity();
        if (options.foot_columns == io::FootCovariance::kDiagonal) {
          foot.cov = Eigen::Matrix3d(foot.cov.diagonal().asDiagonal());
        }
      }
    }
    row.gt_p = base.p;
    row.gt_q = Eigen::Quaterniond(base.R).normalized();
    row.gt_v = base.v;
    if (!options.torque) row.tau.setZero();
    if (!options.force) row.force.fill(0.0);
    if (!options.contact) row.contact.fill(false);
    if (!options.ground_truth) {
      row.gt_p.setZero();
      row.gt_q.setIdentity();
      row.gt_v.setZero();
    }

    const bool dropped =
        inDropout(options.faults, t) || (options.faults.dropout_probability > 0.0 &&
                                         uniform(dropout_rng) < options.faults.dropout_probability);
    if (dropped) continue;
    log.rows.push_back(row);
    out.bias.push_back(bias_now);
  }
  if (log.rows.empty()) throw std::invalid_argument("simulate: every sample was dropped");
  return out;
}

}  // namespace legkit::sim
