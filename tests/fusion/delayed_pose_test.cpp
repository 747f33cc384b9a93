// The filters' pose update (section 57.8, "pose injection"): InvariantEkf::updatePose and
// Eskf::updatePose. Consistency by Monte Carlo (a world-frame pose is a left-invariant observation
// for the right-invariant EKF: its update moves the lever arm [p_hat]_x into the noise, which the
// runs exercise 36 m from the origin; with the linearised H in the world error instead, the
// InvariantEkf's ANEES at the first pose was 12.1, above the bound 10.09), the chi-square gate,
// and bad input.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>

#include "estimation/fusion/delayed_pose.hpp"
#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "lie/imu_dynamics.hpp"
#include "lie/sek3.hpp"

namespace legkit {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using fusion::Matrix6d;
using fusion::PoseMeasurement;
using fusion::PoseUpdate;
using Vector9d = Eigen::Matrix<double, 9, 1>;
using Group = lie::SE23d;  // (R, v, p): the truth

constexpr double kDt = 0.001;   // 1 kHz IMU
constexpr int kSteps = 1000;    // 1 s per run
constexpr int kPoseEvery = 50;  // a pose every 50 ms
constexpr int kRuns = 100;

// Prior sigmas large enough that the poses matter (the library's defaults barely see them).
constexpr double kSigmaAttitude = 0.05, kSigmaVelocity = 0.2, kSigmaPosition = 0.5;

// A full (correlated) SPD pose covariance, (dtheta, dp): 5 mrad and 3 cm scale.
Matrix6d poseCovariance() {
  Matrix6d A;
  A << 4, 1, 0, 0, 0, 1,  //
      0, 5, 1, 0, 1, 0,   //
      1, 0, 6, 1, 0, 0,   //
      0, 0, 2, 20, 3, 0,  //
      0, 1, 0, 0, 25, 4,  //
      1, 0, 0, 2, 0, 30;
  A.topRows<3>() *= 1e-3;
  A.bottomRows<3>() *= 1e-3;
  return A * A.transpose();
}

struct Sampler {
  std::mt19937 rng;
  std::normal_distribution<double> n{0.0, 1.0};
  Vector3d gauss3(double sigma) { return sigma * Vector3d(n(rng), n(rng), n(rng)); }
  Eigen::Matrix<double, 6, 1> gauss6(const Matrix6d& cov) {
    Eigen::Matrix<double, 6, 1> u;
    for (int i = 0; i < 6; ++i) u(i) = n(rng);
    return Matrix6d(cov.llt().matrixL()) * u;
  }
};

// The nominal start, 36 m from the origin and turning.
EstimateSample nominalStart() {
  EstimateSample x;
  x.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Vector3d::UnitZ()) *
                           Eigen::AngleAxisd(0.1, Vector3d::UnitX()));
  x.v = Vector3d(0.5, -0.2, 0.0);
  x.p = Vector3d(30.0, -20.0, 0.4);
  return x;
}

// The kit's error of the estimate, (Log(R R_hat^T), v - v_hat, p - p_hat).
Vector9d baseError(const Group& X, const EstimateSample& e) {
  Vector9d err;
  err.head<3>() =
      lie::SO3d::fromQuaternion(Eigen::Quaterniond(X.R() * e.q.toRotationMatrix().transpose()))
          .Log();
  err.segment<3>(3) = X.col(0) - e.v;
  err.tail<3>() = X.col(1) - e.p;
  return err;
}

// ANEES of one filter type over kRuns runs: after every pose update, the 9-dof NEES of the base,
// averaged over the runs: at the first pose, at the last, and over all of them.
struct Anees {
  double first, last, all;
};
template <class Filter, class Params>
Anees anees(Params params, unsigned seed) {
  params.sigma_attitude = kSigmaAttitude;
  params.sigma_velocity = kSigmaVelocity;
  params.sigma_position = kSigmaPosition;
  const model::ImuNoise& noise = params.imu;
  const Vector3d g = params.gravity;
  const Matrix6d cov = poseCovariance();
  Sampler s{std::mt19937(seed)};
  const int poses = kSteps / kPoseEvery;
  double nees_first = 0.0, nees_last = 0.0, nees_all = 0.0;
  for (int run = 0; run < kRuns; ++run) {
    const EstimateSample x0 = nominalStart();
    // Truth = estimate (+) a draw from the prior, in the kit's convention.
    Group::Columns C;
    C << x0.v + s.gauss3(kSigmaVelocity), x0.p + s.gauss3(kSigmaPosition);
    Group X(lie::SO3d::Exp(s.gauss3(kSigmaAttitude)) * lie::SO3d::fromQuaternion(x0.q), C);
    const Vector3d b_g = s.gauss3(params.sigma_gyro_bias);
    const Vector3d b_a = s.gauss3(params.sigma_accel_bias);
    Filter filter(params);
    filter.reset(x0);
    const Vector3d w(0.3, -0.2, 0.5);  // body rate [rad/s]
    for (int k = 0; k <= kSteps; ++k) {
      const double t = k * kDt;
      const Vector3d a = X.R().transpose() * (-g) + Vector3d(0.5 * std::sin(3.0 * t), 0.2, -0.1);
      StepInput in;
      in.t = t;
      in.dt = k == 0 ? 0.0 : kDt;
      in.imu.w_m = w + b_g + s.gauss3(noise.gyro_noise_density / std::sqrt(kDt));
      in.imu.a_m = a + b_a + s.gauss3(noise.accel_noise_density / std::sqrt(kDt));
      filter.step(in);  // propagates with the previous sample over (t - dt, t]
      if (k > 0 && k % kPoseEvery == 0) {
        const Eigen::Matrix<double, 6, 1> n = s.gauss6(cov);
        PoseMeasurement z;
        z.t = z.t_arrival = t;
        z.R_MB = lie::SO3d::Exp(n.head<3>()) * lie::SO3d::fromQuaternion(Eigen::Quaterniond(X.R()));
        z.p_MB = X.col(1) + n.tail<3>();
        z.cov = cov;
        REQUIRE(filter.updatePose(z) == PoseUpdate::kUsed);
        const Vector9d e = baseError(X, filter.estimate());
        const double nees = e.dot(filter.covariance()->P.ldlt().solve(e));
        nees_all += nees / (kRuns * poses);
        if (k == kPoseEvery) nees_first += nees / kRuns;
        if (k == kSteps) nees_last += nees / kRuns;
      }
      X = lie::imu::propagate(X, w, a, g, kDt);  // the truth over (t, t + dt], same held input
    }
  }
  return {nees_first, nees_last, nees_all};
}

// Two-sided 99 % bounds of the ANEES of `dof` over `runs` runs: runs * ANEES ~ chi2(runs * dof),
// here in its normal approximation (900 dof).
std::pair<double, double> aneesBounds(int dof, int runs) {
  const double n = dof * runs;
  const double half = 2.5758 * std::sqrt(2.0 * n);
  return {(n - half) / runs, (n + half) / runs};
}

PoseMeasurement poseOf(const EstimateSample& e, double t) {
  PoseMeasurement z;
  z.t = z.t_arrival = t;
  z.R_MB = lie::SO3d::fromQuaternion(e.q);
  z.p_MB = e.p;
  z.cov = poseCovariance();
  return z;
}

template <class Filter, class Params>
void checkBadInputAndGate(Params params) {
  params.gating.enabled = true;
  Filter filter(params);
  filter.reset(nominalStart());
  const auto unchanged = [&](const Filter& f) {
    return f.estimate().p == filter.estimate().p &&
           f.estimate().q.coeffs() == filter.estimate().q.coeffs() && f.P() == filter.P();
  };
  PoseMeasurement z = poseOf(filter.estimate(), 1.25);

  SECTION("non-finite or non-SPD: std::invalid_argument naming the field and the time") {
    const auto message = [&](const PoseMeasurement& bad) -> std::string {
      Filter f = filter;
      try {
        f.updatePose(bad);
      } catch (const std::invalid_argument& e) {
        CHECK(unchanged(f));
        return e.what();
      }
      return "no exception";
    };
    PoseMeasurement bad = z;
    bad.p_MB.y() = std::nan("");
    CHECK_THAT(message(bad), Catch::Contains("p_MB is not finite") && Catch::Contains("t = 1.25"));
    bad = z;
    bad.cov(3, 3) = -1.0;
    CHECK_THAT(message(bad), Catch::Contains("cov is not positive definite"));
    bad = z;
    bad.cov(0, 5) += 1.0;
    CHECK_THAT(message(bad), Catch::Contains("cov is not symmetric"));
    bad = z;
    bad.t = INFINITY;
    CHECK_THAT(message(bad), Catch::Contains("PoseMeasurement.t is not finite"));
  }
  SECTION("a pose flagged not valid changes nothing") {
    z.valid = false;
    Filter f = filter;
    CHECK(f.updatePose(z) == PoseUpdate::kNotValid);
    CHECK(unchanged(f));
    CHECK(f.health().total() == 0);
  }
  SECTION("gated beyond the 6-dof chi-square quantile, counted, nothing else changes") {
    Filter f = filter;
    PoseMeasurement far = z;
    far.p_MB.x() += 1.0;  // 1 m: tens of sigma of the prior and the pose together
    CHECK(f.updatePose(far) == PoseUpdate::kGated);
    CHECK(unchanged(f));
    CHECK(f.health()[Fault::kGated] == 1);
    CHECK(f.updatePose(z) == PoseUpdate::kUsed);  // the pose itself passes
    CHECK(f.health()[Fault::kGated] == 1);
    CHECK(f.covariance()->P(6, 6) < filter.covariance()->P(6, 6));
    params.gating.enabled = false;  // without the gate the same pose is used
    Filter open(params);
    open.reset(nominalStart());
    CHECK(open.updatePose(far) == PoseUpdate::kUsed);
    CHECK(open.estimate().p.x() > filter.estimate().p.x() + 1e-3);
  }
}

}  // namespace

TEST_CASE("pose update: the 6-dof gate is the chi-square quantile of the n-sigma rule",
          "[fusion]") {
  engineering::GatingParams gating;
  gating.n_sigma = 3.0;
  // chi2_6 at 0.9973: 20.06 (table)
  CHECK(fusion::poseGateThreshold(gating) == Approx(20.06).margin(0.01));
}

// ANEES after the first pose, the last, and over all poses, each inside the chi-square bounds.
template <class Filter, class Params>
void checkConsistent(const Params& params, unsigned seed) {
  const Anees a = anees<Filter>(params, seed);
  const auto [low, high] = aneesBounds(9, kRuns);
  INFO("ANEES at the first pose " << a.first << ", at the last " << a.last << ", over all " << a.all
                                  << "; bounds [" << low << ", " << high << "]");
  CHECK(a.first > low);  // the first pose meets the prior's widest errors
  CHECK(a.first < high);
  CHECK(a.last > low);
  CHECK(a.last < high);
  CHECK(a.all > low);
  CHECK(a.all < high);
}

TEST_CASE("pose update: InvariantEkf consistent by Monte Carlo (NEES after pose updates)",
          "[fusion]") {
  checkConsistent<invariant::InvariantEkf>(invariant::InvariantEkfParams{}, 57);
}

TEST_CASE("pose update: Eskf consistent by Monte Carlo (NEES after pose updates)", "[fusion]") {
  checkConsistent<invariant::Eskf>(invariant::EskfParams{}, 58);
}

TEST_CASE("pose update: InvariantEkf bad input, valid flag and gate", "[fusion]") {
  checkBadInputAndGate<invariant::InvariantEkf>(invariant::InvariantEkfParams{});
}

TEST_CASE("pose update: Eskf bad input, valid flag and gate", "[fusion]") {
  checkBadInputAndGate<invariant::Eskf>(invariant::EskfParams{});
}

}  // namespace legkit
