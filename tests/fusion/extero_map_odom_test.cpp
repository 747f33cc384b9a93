// The map-to-odom alignment (estimation/fusion/map_odom.hpp): the measurement covariance against
// Monte Carlo, consistency (NEES) and convergence, a loop-closure jump absorbed over the time
// constant with the odometry untouched, every rejection counted, no allocation per update.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <random>

#include "allocation_counter.hpp"
#include "estimation/fusion/map_odom.hpp"

using legkit::fusion::MapOdomAlignment;
using legkit::fusion::MapOdomOptions;
using legkit::fusion::Matrix6d;
using legkit::fusion::OdomHistory;
using legkit::fusion::OdomPose;
using legkit::fusion::PoseMeasurement;
using Outcome = legkit::fusion::MapOdomAlignment::Outcome;
using Vector6d = Eigen::Matrix<double, 6, 1>;

namespace {

struct Rng {
  std::mt19937_64 gen;
  std::normal_distribution<double> normal{0.0, 1.0};
  explicit Rng(unsigned seed) : gen(seed) {}
  Vector6d gaussian(const Matrix6d& cov) {
    Vector6d n;
    for (int i = 0; i < 6; ++i) n(i) = normal(gen);
    return Eigen::LLT<Matrix6d>(cov).matrixL() * n;
  }
};

Matrix6d diag6(double var_r, double var_p) {
  Matrix6d c = Matrix6d::Zero();
  c.diagonal() << var_r, var_r, var_r, var_p, var_p, var_p;
  return c;
}

// (R, p) perturbed in the kit's convention: Exp(e_theta) R, p + e_p.
void perturb(lie::SO3d& R, Eigen::Vector3d& p, const Vector6d& e) {
  R = lie::SO3d::Exp(e.head<3>()) * R;
  p += e.tail<3>();
}

// The odometry's true pose: a circle of radius 3 m at 0.5 m/s, heading along it.
OdomPose odomTruth(double t) {
  OdomPose x;
  x.t = t;
  const double w = 0.5 / 3.0;
  x.R_OB = lie::SO3d::Exp(Eigen::Vector3d(0.0, 0.0, w * t));
  x.p_OB = Eigen::Vector3d(3.0 * std::sin(w * t), 3.0 - 3.0 * std::cos(w * t), 0.0);
  return x;
}

// The (dtheta, dp) error of the estimate about the truth: R_true = Exp(dtheta) R_hat.
Vector6d error(const MapOdomAlignment& f, const lie::SO3d& R_MO, const Eigen::Vector3d& p_MO) {
  Vector6d e;
  e.head<3>() = (R_MO * f.R_MO().inverse()).Log();
  e.tail<3>() = p_MO - f.p_MO();
  return e;
}

// The pose the map would report: T_MB = T_MO T_OB, with noise of covariance cov.
PoseMeasurement measure(const lie::SO3d& R_MO, const Eigen::Vector3d& p_MO, const OdomPose& odom,
                        const Matrix6d& cov, Rng& rng) {
  PoseMeasurement z;
  z.t = odom.t;
  z.t_arrival = odom.t + 0.08;
  z.R_MB = R_MO * odom.R_OB;
  z.p_MB = R_MO.matrix() * odom.p_OB + p_MO;
  z.cov = cov;
  const Vector6d n = rng.gaussian(cov);
  z.R_MB = lie::SO3d::Exp(n.head<3>()) * z.R_MB;
  z.p_MB += n.tail<3>();
  return z;
}

const Matrix6d kPoseCov = diag6(0.005 * 0.005, 0.02 * 0.02);
const Matrix6d kOdomCov = diag6(0.002 * 0.002, 0.01 * 0.01);

}  // namespace

TEST_CASE("map-odom: R_meas maps the pose's and the odometry's covariances (Monte Carlo)",
          "[fusion][extero]") {
  // Far from the odom origin (20 m), so that the lever arm [q]x matters.
  const lie::SO3d R_MO = lie::SO3d::Exp(Eigen::Vector3d(0.1, -0.2, 0.8));
  const Eigen::Vector3d p_MO(4.0, -1.0, 0.2);
  OdomPose odom;
  odom.t = 1.0;
  odom.R_OB = lie::SO3d::Exp(Eigen::Vector3d(0.0, 0.1, 2.0));
  odom.p_OB = Eigen::Vector3d(20.0, -5.0, 1.0);
  Rng rng(5);
  Matrix6d A = Matrix6d::Random() * 0.01;
  odom.cov = A * A.transpose() + diag6(1e-6, 1e-4);
  PoseMeasurement truth;
  truth.t = 1.0;
  truth.R_MB = R_MO * odom.R_OB;
  truth.p_MB = R_MO.matrix() * odom.p_OB + p_MO;
  Matrix6d B = Matrix6d::Random() * 0.01;
  truth.cov = B * B.transpose() + diag6(1e-6, 1e-4);
  const Matrix6d R_meas = MapOdomAlignment::observe(truth, odom, true).cov;

  const int n = 20000;
  Matrix6d sample = Matrix6d::Zero();
  for (int k = 0; k < n; ++k) {
    PoseMeasurement z = truth;
    perturb(z.R_MB, z.p_MB, rng.gaussian(truth.cov));
    OdomPose o = odom;
    // The odometry's estimate: R_true = Exp(alpha) R_hat, i.e. R_hat = Exp(-alpha) R_true.
    perturb(o.R_OB, o.p_OB, -rng.gaussian(odom.cov));
    const auto obs = MapOdomAlignment::observe(z, o, true);
    Vector6d e;
    e.head<3>() = (obs.R_MO * R_MO.inverse()).Log();
    e.tail<3>() = obs.p_MO - p_MO;
    sample += e * e.transpose() / n;
  }
  // Each entry within 5 % of sqrt(R_ii R_jj) (the sampling error is ~1 %).
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      INFO(i << ", " << j << ": sampled " << sample(i, j) << ", R_meas " << R_meas(i, j));
      CHECK(std::abs(sample(i, j) - R_meas(i, j)) < 0.05 * std::sqrt(R_meas(i, i) * R_meas(j, j)));
    }
  }
  // Without the odometry's part, the position block is smaller by the odometry's share.
  const Matrix6d R_pose = MapOdomAlignment::observe(truth, odom, false).cov;
  CHECK(R_pose.trace() < R_meas.trace());
}

TEST_CASE("map-odom: consistent (Monte Carlo NEES) and converging on a walking T_MO",
          "[fusion][extero]") {
  // The odometry noise drawn here is white, independent from one pose to the next, so the model
  // that counts it at every pose is the right one (the default leaves it out: a real odometry's
  // error is a drift, which T_MO's random walk carries).
  MapOdomOptions options;
  options.include_odom_covariance = true;
  const int runs = 400, poses = 100;  // 10 s at 10 Hz each
  std::vector<double> nees(poses, 0.0);
  double final_position_error = 0.0;
  int gated = 0;
  for (int run = 0; run < runs; ++run) {
    Rng rng(1000 + run);
    MapOdomAlignment f(options);
    lie::SO3d R_MO = lie::SO3d::Exp(Eigen::Vector3d(0.01, -0.02, 0.7));
    Eigen::Vector3d p_MO(3.0, -2.0, 0.1);
    for (int k = 0; k < poses; ++k) {
      const double t = 0.1 * k;
      if (k > 0) {  // the truth walks as the filter's model says
        const Vector6d w =
            rng.gaussian(diag6(options.sigma_rotation_walk * options.sigma_rotation_walk * 0.1,
                               options.sigma_position_walk * options.sigma_position_walk * 0.1));
        perturb(R_MO, p_MO, w);
      }
      const OdomPose truth = odomTruth(t);
      const PoseMeasurement z = measure(R_MO, p_MO, truth, kPoseCov, rng);
      OdomPose odom = truth;
      odom.cov = kOdomCov;
      perturb(odom.R_OB, odom.p_OB, rng.gaussian(kOdomCov));
      f.update(z, odom);
      const Vector6d e = error(f, R_MO, p_MO);
      nees[k] += e.dot(f.cov().ldlt().solve(e)) / runs;
      if (k == poses - 1) final_position_error += e.tail<3>().squaredNorm() / runs;
    }
    gated += f.counts().gated;
  }
  double mean = 0.0;
  for (double x : nees) mean += x / poses;
  INFO("NEES averaged over runs and time " << mean << "; first " << nees[0] << " " << nees[1] << " "
                                           << nees[2] << " " << nees[3] << "; at 1 s " << nees[10]
                                           << ", 5 s " << nees[50] << ", 10 s " << nees[99]);
  // Over 400 runs each step's mean is 6 +- sqrt(12 / 400) = 0.17 if consistent; 3.3 sigma.
  for (int k : {10, 50, 99}) CHECK(std::abs(nees[k] - 6.0) < 3.3 * std::sqrt(12.0 / runs));
  CHECK(std::abs(mean - 6.0) < 0.4);
  // The gate (3 sigma: 0.27 % of consistent poses) rejects about that many.
  CHECK(gated < 0.01 * runs * poses);
  // Converged: the position RMS error after 10 s is well under the pose's 2 cm noise.
  INFO("RMS position error after 10 s " << std::sqrt(final_position_error));
  CHECK(std::sqrt(final_position_error) < 0.015);
}

TEST_CASE("map-odom: a loop-closure jump moves T_MO over the time constant, never the odometry",
          "[fusion][extero]") {
  MapOdomOptions options;
  options.include_odom_covariance = false;
  MapOdomAlignment f(options);
  OdomHistory history(2048);
  Rng rng(21);
  const lie::SO3d R_MO = lie::SO3d::Exp(Eigen::Vector3d(0.0, 0.0, -0.4));
  Eigen::Vector3d p_MO(1.0, 2.0, 0.0);
  const Eigen::Vector3d jump(0.3, 0.0, 0.0);
  const double t_jump = 30.0, rate = 10.0;
  std::vector<PoseMeasurement> poses;
  for (int k = 0; k < 10 * 60; ++k) {
    const double t = 0.1 * k;
    poses.push_back(measure(R_MO, t >= t_jump ? Eigen::Vector3d(p_MO + jump) : p_MO, odomTruth(t),
                            kPoseCov, rng));
  }
  // The odometry at 100 Hz: pushed as the filter would, a pose applied once the odometry is past
  // its stamp (the odometry's own covariance left out: include_odom_covariance = false).
  std::size_t next = 0;
  double tau = 0.0, settled = NAN, largest_step = 0.0;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  std::vector<OdomPose> pushed;
  for (int j = 0; j < 100 * 60; ++j) {
    OdomPose x = odomTruth(0.01 * j);
    x.cov = kOdomCov;
    history.push(x);
    pushed.push_back(x);
    while (next < poses.size() && poses[next].t <= x.t) {
      const PoseMeasurement& z = poses[next++];
      const Outcome outcome = f.update(z, history);
      CHECK(outcome != Outcome::kTooOld);
      if (z.t < t_jump) {
        // The time constant the header states, from the last measurement before the jump.
        const auto odom = history.at(z.t).pose;
        const double s_z = std::sqrt(MapOdomAlignment::observe(z, odom, false).cov(3, 3));
        tau = s_z / (options.sigma_position_walk * std::sqrt(rate));
      } else {
        largest_step = std::max(largest_step, (f.p_MO() - previous).norm());
        const double left = (f.p_MO() - (p_MO + jump)).dot(jump.normalized());
        if (std::isnan(settled) && std::abs(left) < jump.norm() / std::exp(1.0)) settled = z.t;
      }
      previous = f.p_MO();
    }
  }
  const double confirm = options.jump_confirm_time;
  INFO("tau " << tau << " s, jump down to 1/e after " << settled - t_jump << " s (confirmation "
              << confirm << " s), largest step " << largest_step << " m, gated " << f.counts().gated
              << ", jump updates " << f.counts().jump_updates);
  // Gated for jump_confirm_time (5 poses, plus the few the noise gates), then taken ungated.
  CHECK(f.counts().gated >= 5);
  CHECK(f.counts().gated <= 5 + 10);
  CHECK(f.counts().jump_updates >= 1);
  // Absorbed over the time constant, not in one step.
  REQUIRE(!std::isnan(settled));
  CHECK(settled - t_jump > confirm + 0.5 * tau);
  CHECK(settled - t_jump < confirm + 2.0 * tau);
  CHECK(largest_step < 0.25 * jump.norm());
  // And T_MO ends at the new map, within its noise.
  CHECK((f.p_MO() - (p_MO + jump)).norm() < 0.03);

  // The odometry the controller reads is untouched, bitwise.
  for (const auto& x : pushed) {
    if (x.t < history.oldestTime()) continue;
    const auto r = history.at(x.t);
    CHECK(std::memcmp(r.pose.R_OB.matrix().data(), x.R_OB.matrix().data(), 9 * sizeof(double)) ==
          0);
    CHECK(std::memcmp(r.pose.p_OB.data(), x.p_OB.data(), 3 * sizeof(double)) == 0);
    CHECK(std::memcmp(r.pose.cov.data(), x.cov.data(), 36 * sizeof(double)) == 0);
  }
}

TEST_CASE("map-odom: every rejection counted with its reason, the estimate untouched",
          "[fusion][extero]") {
  OdomHistory history(256);
  for (int j = 50; j <= 200; ++j) {
    OdomPose x = odomTruth(0.01 * j);
    x.cov = kOdomCov;
    history.push(x);
  }
  Rng rng(3);
  const lie::SO3d R_MO = lie::SO3d::Exp(Eigen::Vector3d(0.0, 0.0, 0.3));
  const Eigen::Vector3d p_MO(1.0, 0.0, 0.0);
  const auto pose = [&](double t) { return measure(R_MO, p_MO, odomTruth(t), kPoseCov, rng); };
  MapOdomAlignment f;
  CHECK(f.update(pose(0.6), history) == Outcome::kInitialised);

  const auto unchanged = [&](PoseMeasurement z, Outcome expected) {
    const MapOdomAlignment before = f;
    CHECK(f.update(z, history) == expected);
    CHECK(f.R_MO().matrix() == before.R_MO().matrix());
    CHECK(f.p_MO() == before.p_MO());
    if (expected != Outcome::kGated) CHECK(f.cov() == before.cov());
  };
  PoseMeasurement z = pose(0.7);
  z.valid = false;
  unchanged(z, Outcome::kInvalid);
  z = pose(0.7);
  z.p_MB.y() = std::nan("");
  unchanged(z, Outcome::kNonFinite);
  z = pose(0.7);
  z.cov(3, 3) = -1e-4;
  unchanged(z, Outcome::kBadCovariance);
  unchanged(pose(0.6), Outcome::kOutOfOrder);  // the same stamp again
  unchanged(pose(0.4), Outcome::kTooOld);      // before the history's 0.5 s
  unchanged(pose(2.5), Outcome::kInFuture);    // after its newest sample, 2.0 s
  z = pose(0.7);
  z.p_MB.x() += 1.0;  // one outlier, 1 m
  unchanged(z, Outcome::kGated);
  CHECK(f.lastMahalanobis() > f.gateThreshold());
  CHECK(f.update(pose(0.8), history) == Outcome::kUsed);
  const auto& c = f.counts();
  CHECK(c.initialised == 1);
  CHECK(c.used == 1);
  CHECK(c.invalid == 1);
  CHECK(c.non_finite == 1);
  CHECK(c.bad_covariance == 1);
  CHECK(c.out_of_order == 1);
  CHECK(c.too_old == 1);
  CHECK(c.in_future == 1);
  CHECK(c.gated == 1);
  CHECK(c.rejected() == 7);
  // The 3-sigma gate of 6 dof: the chi-square quantile at erf(3 / sqrt 2) = 0.9973.
  CHECK(f.gateThreshold() == Approx(20.062).epsilon(1e-4));

  // Pairing a pose with an odometry pose of another time is a programming error.
  OdomPose newest = history.at(2.0).pose;
  CHECK_THROWS_WITH(f.update(pose(0.9), newest),
                    Catch::Contains("use the odometry at the pose's stamp"));
  CHECK_THROWS_WITH(MapOdomAlignment(MapOdomOptions{-1.0}),
                    Catch::StartsWith("MapOdomOptions.sigma_rotation_walk"));
  MapOdomOptions bad;
  bad.n_sigma = 0.0;
  CHECK_THROWS_WITH(MapOdomAlignment(bad), Catch::StartsWith("MapOdomOptions.n_sigma"));
}

TEST_CASE("map-odom: mapPose is T_MO T_OB; update allocates nothing", "[fusion][extero]") {
  OdomHistory history(2048);
  std::vector<PoseMeasurement> poses;
  Rng rng(9);
  const lie::SO3d R_MO = lie::SO3d::Exp(Eigen::Vector3d(0.1, 0.0, 1.0));
  const Eigen::Vector3d p_MO(-2.0, 5.0, 0.5);
  for (int j = 0; j < 2000; ++j) {
    OdomPose x = odomTruth(0.01 * j);
    x.cov = kOdomCov;
    history.push(x);
    if (j % 10 == 5) poses.push_back(measure(R_MO, p_MO, x, kPoseCov, rng));
  }
  MapOdomAlignment f;
  const long before = legkit::test::allocationCount();
  for (const auto& z : poses) f.update(z, history);
  CHECK(legkit::test::allocationCount() == before);
  CHECK(f.counts().used + f.counts().gated + f.counts().initialised ==
        static_cast<int>(poses.size()));

  const OdomPose x = odomTruth(12.34);
  const auto m = f.mapPose(x.R_OB, x.p_OB);
  CHECK((m.R_MB.matrix() - f.R_MO().matrix() * x.R_OB.matrix()).norm() < 1e-15);
  CHECK((m.p_MB - (f.R_MO().matrix() * x.p_OB + f.p_MO())).norm() < 1e-14);
  // Close to the true map pose: T_MO has converged.
  CHECK((m.p_MB - (R_MO.matrix() * x.p_OB + p_MO)).norm() < 0.03);
}
