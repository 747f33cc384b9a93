#include "estimation/fusion/fixed_lag_smoother.hpp"

#include <ceres/crs_matrix.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <ctime>
#include <deque>
#include <stdexcept>
#include <string>
#include <vector>

#include "estimation/fusion/factors.hpp"
#include "estimation/fusion/keyframe.hpp"
#include "estimation/fusion/leg_preintegration.hpp"
#include "estimation/fusion/marginalization.hpp"
#include "estimation/health_guard.hpp"
#include "estimation/imu/preintegration.hpp"
#include "estimation/leg_odometry/velocity_fusion.hpp"
#include "lie/ceres/manifolds.hpp"

namespace legkit::fusion {

namespace {

// The message is built only on failure: a passing check does not allocate.
void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("FixedLagSmoother: ") + what);
}

bool positive(double x) {
  return x > 0.0 && std::isfinite(x);
}

// CPU time of the calling thread [s]: the solve's cost on one core, whatever else the machine runs.
double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// The increments since the keyframe of its interval at one sample: where the smoother's own motion
// puts the base at that sample, given the keyframe's current state.
struct HistorySample {
  double t = 0.0;
  double t_keyframe = 0.0;  // the keyframe the interval started at
  double dt = 0.0;          // t - t_keyframe
  Eigen::Matrix3d dR = Eigen::Matrix3d::Identity();
  Eigen::Vector3d dp = Eigen::Vector3d::Zero();
};

// The history holds up to this many samples per second of window (2 kHz).
constexpr double kHistoryRate = 2000.0;

}  // namespace

struct FixedLagSmoother::Impl {
  SmootherOptions o;
  Stats stats;
  lie::ceres::SO3Manifold so3;
  std::unique_ptr<ceres::Problem> problem;
  std::deque<Keyframe> window;  // deque: pointers to the blocks stay valid at both ends
  imu::Preintegrator pim;
  LegPreintegrator lpi;
  bool initialised = false;
  bool has_previous = false;
  bool legs_whole_interval = true;  // every sample of the interval had a stance foot
  double t_now = 0.0, sample_dt = 0.0;
  // The previous sample, held over the next dt: IMU reading, legs' body-frame velocity, the mean
  // body-frame position of the stance feet and their number.
  model::ImuReading held_imu;
  bool held_legs = false;
  Eigen::Vector3d held_v = Eigen::Vector3d::Zero(), held_r = Eigen::Vector3d::Zero();
  int held_feet = 0;
  std::vector<HistorySample> history;  // ring buffer
  std::size_t history_head = 0, history_size = 0;
  std::vector<PoseMeasurement> pending;  // stamped after the newest keyframe's half interval

  explicit Impl(SmootherOptions options)
      : o(std::move(options)),
        pim({}, o.imu),
        lpi(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), o.imu) {}

  Keyframe& newest() { return window.back(); }
  const Keyframe& newest() const { return window.back(); }

  void addBlocks(Keyframe& k) {
    problem->AddParameterBlock(k.R.data(), 9, &so3);
    problem->AddParameterBlock(k.v.data(), 3);
    problem->AddParameterBlock(k.p.data(), 3);
    problem->AddParameterBlock(k.b_g.data(), 3);
    problem->AddParameterBlock(k.b_a.data(), 3);
    problem->AddParameterBlock(k.b_v.data(), 3);
    if (!o.velocity_bias) problem->SetParameterBlockConstant(k.b_v.data());
  }

  static imu::NavState nav(const Keyframe& k) {
    return {lie::SO3d::fromMatrix(k.Rmat(), 1e-6), Eigen::Map<const Eigen::Vector3d>(k.v.data()),
            Eigen::Map<const Eigen::Vector3d>(k.p.data())};
  }
  static model::ImuBias bias(const Keyframe& k) {
    return {Eigen::Map<const Eigen::Vector3d>(k.b_g.data()),
            Eigen::Map<const Eigen::Vector3d>(k.b_a.data())};
  }

  // Both preintegrators start over at the newest keyframe's biases.
  void restartIntervals() {
    const Keyframe& k = newest();
    pim = imu::Preintegrator(bias(k), o.imu);
    lpi = LegPreintegrator(Eigen::Map<const Eigen::Vector3d>(k.b_g.data()),
                           Eigen::Map<const Eigen::Vector3d>(k.b_v.data()), o.imu);
    legs_whole_interval = true;
  }

  void pushHistory(double t) {
    HistorySample& s = history[(history_head + history_size) % history.size()];
    s.t = t;
    s.t_keyframe = newest().t;
    s.dt = pim.dt_ij();
    s.dR = pim.dR().matrix();
    s.dp = pim.dp();
    if (history_size < history.size())
      ++history_size;
    else
      history_head = (history_head + 1) % history.size();
  }

  const HistorySample* historyAt(double t) const {
    const HistorySample* best = nullptr;
    for (std::size_t i = 0; i < history_size; ++i) {
      const HistorySample& s = history[(history_head + i) % history.size()];
      if (!best || std::abs(s.t - t) < std::abs(best->t - t)) best = &s;
    }
    return best && std::abs(best->t - t) <= 0.5 * sample_dt + 1e-9 ? best : nullptr;
  }

  const Keyframe* keyframeAt(double t) const {
    for (const Keyframe& k : window)
      if (std::abs(k.t - t) <= 1e-9) return &k;
    return nullptr;
  }

  // Attaches z to the keyframe nearest its stamp (carried there by the smoother's own motion when
  // it is not at the keyframe's instant). False when the motion to carry it is no longer known.
  bool attach(const PoseMeasurement& z) {
    Keyframe* k = &window.front();
    for (Keyframe& candidate : window)
      if (std::abs(candidate.t - z.t) < std::abs(k->t - z.t)) k = &candidate;
    PoseMeasurement at_k = z;
    if (std::abs(k->t - z.t) > 0.5 * sample_dt + 1e-9) {
      const HistorySample* s = historyAt(z.t);
      const Keyframe* a = s ? keyframeAt(s->t_keyframe) : nullptr;
      if (!a) return false;
      // Where the smoother puts the base at z.t: R(t_z) = R_a dR, p(t_z) = p_a + v_a dt +
      // g dt^2 / 2 + R_a dp (the preintegration constraint).
      const Eigen::Matrix3d R_a = a->Rmat();
      const Eigen::Matrix3d R_z = R_a * s->dR;
      const Eigen::Vector3d p_z = Eigen::Map<const Eigen::Vector3d>(a->p.data()) +
                                  Eigen::Map<const Eigen::Vector3d>(a->v.data()) * s->dt +
                                  0.5 * o.gravity * s->dt * s->dt + R_a * s->dp;
      const Eigen::Matrix3d R_k = k->Rmat();
      // R_meas,k = R_meas R(t_z)^T R_k, p_meas,k = p_meas - (p(t_z) - p_k).
      at_k.R_MB = lie::SO3d::fromQuaternion(
          Eigen::Quaterniond(z.R_MB.matrix() * R_z.transpose() * R_k).normalized());
      at_k.p_MB = z.p_MB - (p_z - Eigen::Map<const Eigen::Vector3d>(k->p.data()));
    }
    problem->AddResidualBlock(new PoseFactor(at_k), nullptr, k->R.data(), k->p.data());
    ++stats.poses_used;
    return true;
  }

  void attachPending() {
    std::size_t kept = 0;
    for (const PoseMeasurement& z : pending) {
      if (z.t <= newest().t + 0.5 * o.keyframe_dt) {
        if (!attach(z)) ++stats.poses_rejected;
      } else {
        pending[kept++] = z;
      }
    }
    pending.resize(kept);
  }

  void solve() {
    ceres::Solver::Options options;
    options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.max_num_iterations = o.max_iterations;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = threadCpuSeconds();
    ceres::Solve(options, problem.get(), &summary);
    stats.last_solve_cpu_s = threadCpuSeconds() - cpu_start;
    stats.last_solve_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.last_iterations = static_cast<int>(summary.iterations.size()) - 1;
    ++stats.solves;
  }

  // Keyframe j at time t: blocks predicted by the IMU, the factors of the interval, pending poses,
  // one solve, then the oldest keyframes marginalised until the window fits.
  void addKeyframe(double t) {
    const Keyframe& i_now = newest();
    const imu::NavState x_j = pim.predict(nav(i_now), bias(i_now), o.gravity);
    Keyframe j = i_now;
    j.t = t;
    Eigen::Map<Eigen::Matrix3d>(j.R.data()) = x_j.R.matrix();
    Eigen::Map<Eigen::Vector3d>(j.v.data()) = x_j.v;
    Eigen::Map<Eigen::Vector3d>(j.p.data()) = x_j.p;
    window.push_back(j);
    Keyframe& kj = window.back();
    Keyframe& ki = window[window.size() - 2];
    addBlocks(kj);
    problem->AddResidualBlock(new ImuFactor(pim, o.gravity), nullptr,
                              {ki.R.data(), ki.v.data(), ki.p.data(), kj.R.data(), kj.v.data(),
                               kj.p.data(), ki.b_g.data(), ki.b_a.data()});
    if (legs_whole_interval && lpi.dt_ij() > 0.0)
      problem->AddResidualBlock(
          new LegOdometryFactor(lpi), nullptr,
          {ki.R.data(), ki.p.data(), kj.p.data(), ki.b_v.data(), ki.b_g.data()});
    else
      ++stats.leg_intervals_skipped;
    const double dt = pim.dt_ij();
    problem->AddResidualBlock(new BiasWalkFactor(o.imu.gyro_bias_random_walk, dt), nullptr,
                              ki.b_g.data(), kj.b_g.data());
    problem->AddResidualBlock(new BiasWalkFactor(o.imu.accel_bias_random_walk, dt), nullptr,
                              ki.b_a.data(), kj.b_a.data());
    if (o.velocity_bias)
      problem->AddResidualBlock(new BiasWalkFactor(o.bias_v_walk, dt), nullptr, ki.b_v.data(),
                                kj.b_v.data());
    attachPending();
    solve();
    while (window.size() > 2 && newest().t - window.front().t > o.window + 0.5 * o.keyframe_dt) {
      Keyframe& old = window.front();
      marginalizeOut(*problem, {old.R.data(), old.v.data(), old.p.data(), old.b_g.data(),
                                old.b_a.data(), old.b_v.data()});
      window.pop_front();
      ++stats.marginalised;
    }
    stats.keyframes = static_cast<int>(window.size());
    restartIntervals();
  }
};

FixedLagSmoother::FixedLagSmoother(SmootherOptions o) {
  require(positive(o.keyframe_dt), "keyframe_dt must be positive and finite");
  require(std::isfinite(o.window) && o.window >= 2.0 * o.keyframe_dt,
          "window must be at least two keyframe_dt");
  require(positive(o.imu.gyro_noise_density) && positive(o.imu.accel_noise_density) &&
              positive(o.imu.gyro_bias_random_walk) && positive(o.imu.accel_bias_random_walk),
          "imu noise densities must be positive and finite");
  require(positive(o.leg_velocity_sigma), "leg_velocity_sigma must be positive and finite");
  require(positive(o.bias_v_walk), "bias_v_walk must be positive and finite");
  require(o.gravity.allFinite(), "gravity must be finite");
  for (const double s : {o.prior_sigma_tilt, o.prior_sigma_yaw, o.prior_sigma_v, o.prior_sigma_p,
                         o.prior_sigma_bg, o.prior_sigma_ba, o.prior_sigma_bv})
    require(positive(s), "prior sigmas must be positive and finite");
  require(o.max_iterations >= 1, "max_iterations must be at least 1");
  impl_ = std::make_unique<Impl>(std::move(o));
  const SmootherOptions& opt = impl_->o;
  impl_->history.resize(
      static_cast<std::size_t>(std::ceil(kHistoryRate * (opt.window + 2.0 * opt.keyframe_dt))));
  impl_->pending.reserve(16);
}

FixedLagSmoother::~FixedLagSmoother() = default;
FixedLagSmoother::FixedLagSmoother(FixedLagSmoother&&) noexcept = default;
FixedLagSmoother& FixedLagSmoother::operator=(FixedLagSmoother&&) noexcept = default;

void FixedLagSmoother::initialise(const InitialState& s) {
  checkInitialState(s, "FixedLagSmoother");
  Impl& m = *impl_;
  const SmootherOptions& o = m.o;
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;  // the one SO3Manifold
  problem_options.enable_fast_removal = true;
  m.problem = std::make_unique<ceres::Problem>(problem_options);
  m.window.clear();
  Keyframe k0;
  k0.t = s.x.t;
  const Eigen::Matrix3d R0 = s.x.q.normalized().toRotationMatrix();
  k0.Rmat() = R0;
  Eigen::Map<Eigen::Vector3d>(k0.v.data()) = s.x.v;
  Eigen::Map<Eigen::Vector3d>(k0.p.data()) = s.x.p;
  Eigen::Map<Eigen::Vector3d>(k0.b_g.data()) = s.b_g;
  Eigen::Map<Eigen::Vector3d>(k0.b_a.data()) = s.b_a;
  m.window.push_back(k0);
  Keyframe& k = m.window.back();
  m.addBlocks(k);

  // The first keyframe's prior, r = W (x (-) x0): the attitude's in the world frame,
  // dtheta = R0 delta, so its rows are diag(1/sigma) R0.
  const double sigma_tilt = std::isnan(s.sigma_tilt) ? o.prior_sigma_tilt : s.sigma_tilt;
  std::vector<LinearPrior::Block> blocks;
  const auto block = [&](std::array<double, 3>& x) {
    blocks.push_back({x.data(), nullptr, std::vector<double>(x.begin(), x.end()), 3});
  };
  blocks.push_back({k.R.data(), &m.so3, std::vector<double>(k.R.begin(), k.R.end()), 3});
  block(k.v);
  block(k.p);
  block(k.b_g);
  block(k.b_a);
  if (o.velocity_bias) block(k.b_v);
  const int n = 3 * static_cast<int>(blocks.size());
  Eigen::MatrixXd J0 = Eigen::MatrixXd::Zero(n, n);
  J0.topLeftCorner<3, 3>() =
      Eigen::Vector3d(1.0 / sigma_tilt, 1.0 / sigma_tilt, 1.0 / o.prior_sigma_yaw).asDiagonal() *
      R0;
  const double sigmas[] = {o.prior_sigma_v, o.prior_sigma_p, o.prior_sigma_bg, o.prior_sigma_ba,
                           o.prior_sigma_bv};
  for (Eigen::Index b = 1; b < static_cast<Eigen::Index>(blocks.size()); ++b)
    J0.block<3, 3>(3 * b, 3 * b) = Eigen::Matrix3d::Identity() / sigmas[b - 1];
  auto prior = std::make_unique<LinearPrior>(std::move(blocks), J0, Eigen::VectorXd::Zero(n));
  const std::vector<double*> prior_blocks = prior->parameterBlocks();
  m.problem->AddResidualBlock(prior.release(), nullptr, prior_blocks);

  m.stats = Stats{};
  m.stats.keyframes = 1;
  m.has_previous = false;
  m.held_legs = false;
  m.t_now = s.x.t;
  m.history_head = m.history_size = 0;
  m.pending.clear();
  m.initialised = true;
  m.restartIntervals();
}

void FixedLagSmoother::addStep(const StepInput& in) {
  Impl& m = *impl_;
  require(m.initialised, "addStep before initialise");
  checkStepInput(in, leg_odometry::kMaxContacts, "FixedLagSmoother");
  if (m.has_previous && in.dt > 0.0) {
    // The previous sample held over dt: the IMU increments and the legs' displacement.
    m.pim.integrate(m.held_imu, in.dt);
    if (m.held_legs) {
      // Per-sample covariance of the body-frame leg velocity v = -(w_b x r + r_dot) averaged over
      // the k stance feet: the gyro's white noise through the mean foot position r, plus the
      // feet's own (independent) velocity noise.
      const Eigen::Matrix3d r_x = lie::SO3d::hat(m.held_r);
      const double gyro_var = m.o.imu.gyro_noise_density * m.o.imu.gyro_noise_density / in.dt;
      const double leg_var = m.o.leg_velocity_sigma * m.o.leg_velocity_sigma / in.dt / m.held_feet;
      const Eigen::Matrix3d Sigma_v =
          gyro_var * r_x * r_x.transpose() + leg_var * Eigen::Matrix3d::Identity();
      m.lpi.integrate(m.held_imu.w_m, m.held_v, Sigma_v, in.dt);
    } else {
      m.legs_whole_interval = false;
    }
    m.sample_dt = in.dt;
    m.pushHistory(in.t);
  }
  // This sample, held over the next interval.
  m.held_imu = in.imu;
  m.held_legs = in.num_contacts > 0;
  for (int c = 0; c < in.num_contacts; ++c) m.held_legs = m.held_legs && in.contacts[c].v_body;
  if (m.held_legs) {
    const Eigen::Vector3d w_b =
        in.imu.w_m - Eigen::Map<const Eigen::Vector3d>(m.newest().b_g.data());
    m.held_v = leg_odometry::meanVelocity(Eigen::Matrix3d::Identity(), w_b, in.stance());
    m.held_r.setZero();
    for (int c = 0; c < in.num_contacts; ++c) m.held_r += in.contacts[c].p_body;
    m.held_r /= in.num_contacts;
    m.held_feet = in.num_contacts;
  }
  const bool integrated = m.has_previous && in.dt > 0.0;
  m.has_previous = true;
  m.t_now = in.t;
  if (integrated && in.t + 0.5 * in.dt >= m.newest().t + m.o.keyframe_dt) m.addKeyframe(in.t);
}

void FixedLagSmoother::addPose(const PoseMeasurement& z) {
  Impl& m = *impl_;
  require(m.initialised, "addPose before initialise");
  if (!z.valid) {
    ++m.stats.poses_invalid;
    return;
  }
  require(std::isfinite(z.t), "pose stamp must be finite");
  if (!(z.t <= m.t_now + 1e-9))
    throw std::invalid_argument("FixedLagSmoother: pose stamped t = " + std::to_string(z.t) +
                                " after the newest sample t = " + std::to_string(m.t_now));
  const PoseFactor check(z);  // throws for a non-finite pose or a covariance that is not SPD
  if (z.t < m.window.front().t - 0.5 * m.o.keyframe_dt) {
    ++m.stats.poses_rejected;
    return;
  }
  if (z.t <= m.newest().t + 0.5 * m.o.keyframe_dt) {
    if (!m.attach(z)) ++m.stats.poses_rejected;
  } else {
    m.pending.push_back(z);
  }
}

EstimateSample FixedLagSmoother::keyframeEstimate() const {
  require(impl_->initialised, "keyframeEstimate before initialise");
  const Keyframe& k = impl_->newest();
  EstimateSample x;
  x.t = k.t;
  x.q = Eigen::Quaterniond(k.Rmat()).normalized();
  x.v = Eigen::Map<const Eigen::Vector3d>(k.v.data());
  x.p = Eigen::Map<const Eigen::Vector3d>(k.p.data());
  return x;
}

EstimateSample FixedLagSmoother::estimate() const {
  const Impl& m = *impl_;
  require(m.initialised, "estimate before initialise");
  if (m.pim.dt_ij() <= 0.0) return keyframeEstimate();
  const Keyframe& k = m.newest();
  const imu::NavState x = m.pim.predict(Impl::nav(k), Impl::bias(k), m.o.gravity);
  EstimateSample e;
  e.t = m.t_now;
  e.q = x.R.quaternion().normalized();
  e.v = x.v;
  e.p = x.p;
  return e;
}

BaseCovariance FixedLagSmoother::keyframeCovariance() const {
  const Impl& m = *impl_;
  require(m.initialised, "keyframeCovariance before initialise");
  const Keyframe& k = m.newest();
  // Every free block of the window, the newest keyframe's R, v, p last (9 tangent columns).
  std::vector<double*> blocks;
  for (const Keyframe& kf : m.window) {
    for (const double* x :
         {kf.R.data(), kf.v.data(), kf.p.data(), kf.b_g.data(), kf.b_a.data(), kf.b_v.data()}) {
      const bool newest_state =
          &kf == &k && (x == k.R.data() || x == k.v.data() || x == k.p.data());
      if (!newest_state && !m.problem->IsParameterBlockConstant(x))
        blocks.push_back(const_cast<double*>(x));
    }
  }
  for (const double* x : {k.R.data(), k.v.data(), k.p.data()})
    blocks.push_back(const_cast<double*>(x));
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = blocks;
  ceres::CRSMatrix crs;
  m.problem->Evaluate(options, nullptr, nullptr, nullptr, &crs);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(crs.num_cols, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int a = crs.rows[r]; a < crs.rows[r + 1]; ++a)
      for (int b = crs.rows[r]; b < crs.rows[r + 1]; ++b)
        H(crs.cols[a], crs.cols[b]) += crs.values[a] * crs.values[b];
  const int n = crs.num_cols;
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, 9);
  E.bottomRows<9>().setIdentity();
  const Eigen::Matrix<double, 9, 9> C = H.llt().solve(E).bottomRows<9>();
  // Tangent (delta, dv, dp) with R = R_hat Exp(delta) -> (dtheta, dv, dp), dtheta = R_hat delta.
  Eigen::Matrix<double, 9, 9> T = Eigen::Matrix<double, 9, 9>::Identity();
  T.topLeftCorner<3, 3>() = k.Rmat();
  BaseCovariance P;
  P.P = T * C * T.transpose();
  P.P = 0.5 * (P.P + P.P.transpose()).eval();
  return P;
}

Eigen::Vector3d FixedLagSmoother::velocityBias() const {
  require(impl_->initialised, "velocityBias before initialise");
  return Eigen::Map<const Eigen::Vector3d>(impl_->newest().b_v.data());
}
Eigen::Vector3d FixedLagSmoother::gyroBias() const {
  require(impl_->initialised, "gyroBias before initialise");
  return Eigen::Map<const Eigen::Vector3d>(impl_->newest().b_g.data());
}
Eigen::Vector3d FixedLagSmoother::accelBias() const {
  require(impl_->initialised, "accelBias before initialise");
  return Eigen::Map<const Eigen::Vector3d>(impl_->newest().b_a.data());
}
const FixedLagSmoother::Stats& FixedLagSmoother::stats() const {
  return impl_->stats;
}
const SmootherOptions& FixedLagSmoother::options() const {
  return impl_->o;
}

}  // namespace legkit::fusion
