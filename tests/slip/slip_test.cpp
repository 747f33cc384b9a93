// Section 57.7: the slip detector's residual, covariance and chi-square test with hand values, the
// attitude block of H checked by sampling, the multi-foot outlier on four feet, the all-feet test
// (IMU against the legs), the reactions on a StepInput, the ground plane and the terrain classes.
#include <rapidcheck.h>
#include <rapidcheck/catch.h>
#include <catch2/catch.hpp>
#include <cmath>
#include <lie/so3.hpp>
#include <random>

#include "allocation_counter.hpp"
#include "estimation/slip/plane_fit.hpp"
#include "estimation/slip/slip_guard.hpp"
#include "estimation/slip/terrain.hpp"
#include "model/imu_model.hpp"

using namespace legkit;        // NOLINT(google-build-using-namespace)
using namespace legkit::slip;  // NOLINT(google-build-using-namespace)
using Approx = Catch::Detail::Approx;

namespace {

// A foot slips at its first exceeded check (no confirmation).
SlipParams instant() {
  SlipParams p;
  p.confirm_samples = 1;
  return p;
}

// Parameters without the gyro term, so that R_i = foot_velocity_sigma^2 I exactly.
SlipParams handParams() {
  SlipParams p = instant();
  p.gyro_sigma = 0.0;
  p.foot_velocity_sigma = 0.05;
  return p;
}

// A stance foot at p whose body-frame velocity makes v_leg = -R (w x p + v_body) equal v_leg.
ContactMeasurement footGiving(int id, const Eigen::Vector3d& p, const Eigen::Vector3d& v_leg,
                              const Eigen::Matrix3d& R, const Eigen::Vector3d& w) {
  ContactMeasurement c;
  c.foot = id;
  c.p_body = p;
  c.cov = Eigen::Matrix3d::Identity() * 1e-6;
  c.v_body = Eigen::Vector3d(-R.transpose() * v_leg - w.cross(p));
  return c;
}

const std::array<Eigen::Vector3d, 4> kFeet = {
    Eigen::Vector3d(0.2, 0.15, -0.3), Eigen::Vector3d(0.2, -0.15, -0.3),
    Eigen::Vector3d(-0.2, 0.15, -0.3), Eigen::Vector3d(-0.2, -0.15, -0.3)};

// Four feet all giving v_leg, plus `extra` on foot `slipper` (-1: none).
StepInput fourFeet(double t, const Eigen::Vector3d& v_leg, int slipper = -1,
                   const Eigen::Vector3d& extra = Eigen::Vector3d::Zero()) {
  StepInput in;
  in.t = t;
  in.dt = 0.001;
  in.imu.a_m = -model::gravity();  // level, not accelerating
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d v = i == slipper ? Eigen::Vector3d(v_leg + extra) : v_leg;
    in.contacts[i] = footGiving(i, kFeet[i], v, Eigen::Matrix3d::Identity(), in.imu.w_m);
    in.normal_force[i] = 50.0 + i;
  }
  in.num_contacts = 4;
  in.has_force = true;
  return in;
}

BaseCovariance velocityOnly(double sigma) {
  BaseCovariance P;
  P.has_attitude = false;
  P.P.block<3, 3>(3, 3) = Eigen::Matrix3d::Identity() * sigma * sigma;
  return P;
}

}  // namespace

TEST_CASE("chi2_3 quantile: 11.345 at alpha = 0.99 (exercise 57.7.1)", "[57.7][slip]") {
  CHECK(chi2Quantile3(0.99) == Approx(11.3449).margin(1e-4));
  CHECK(chi2Quantile3(0.95) == Approx(7.8147).margin(1e-4));
  CHECK(chi2Quantile3(0.5) == Approx(2.3660).margin(1e-4));
  CHECK_THROWS_AS(chi2Quantile3(1.0), std::invalid_argument);
  CHECK_THROWS_AS(chi2Quantile3(0.0), std::invalid_argument);
  CHECK(SlipDetector().threshold() == Approx(11.3449).margin(1e-4));
}

TEST_CASE("residual, S and d2 by hand, velocity block only", "[57.7][slip]") {
  SlipDetector detector(handParams());
  StepInput in;
  in.t = 1.0;
  in.num_contacts = 1;
  in.contacts[0] = footGiving(3, kFeet[3], Eigen::Vector3d(0.5, 0, 0), Eigen::Matrix3d::Identity(),
                              Eigen::Vector3d::Zero());
  EstimateSample x;
  x.t = 1.0;
  x.v = Eigen::Vector3d(0.4, 0, 0);
  // S = P_vv + R_i = (0.01 + 0.0025) I; r = (0.1, 0, 0): d2 = 0.01 / 0.0125 = 0.8.
  SlipReport r = detector.check(in, x, velocityOnly(0.1));
  REQUIRE(r.num_feet == 1);
  CHECK(r.feet[0].foot == 3);
  CHECK(r.feet[0].v_leg.isApprox(Eigen::Vector3d(0.5, 0, 0), 1e-12));
  CHECK(r.feet[0].residual.isApprox(Eigen::Vector3d(0.1, 0, 0), 1e-12));
  CHECK(r.feet[0].S.isApprox(Eigen::Matrix3d::Identity() * 0.0125, 1e-12));
  CHECK(r.feet[0].d2 == Approx(0.8));
  CHECK_FALSE(r.feet[0].slipping);
  // r = (0.5, 0, 0): d2 = 0.25 / 0.0125 = 20 > 11.345.
  detector.reset();
  x.v.setZero();
  r = detector.check(in, x, velocityOnly(0.1));
  CHECK(r.feet[0].d2 == Approx(20.0));
  CHECK(r.feet[0].slipping);
  CHECK(r.slipping(3));
  CHECK_FALSE(r.slipping(0));
  CHECK(r.all_slipping);  // its only stance foot slips
}

TEST_CASE("attitude uncertainty enters S across v_leg, not along it", "[57.7][slip]") {
  // v_leg = (0.5, 0, 0), P_thth = 0.01 I: H P H^T = 0.01 [v]_x [v]_x^T = 0.0025 diag(0, 1, 1).
  SlipDetector detector(handParams());
  StepInput in;
  in.t = 2.0;
  in.num_contacts = 1;
  in.contacts[0] = footGiving(0, kFeet[0], Eigen::Vector3d(0.5, 0, 0), Eigen::Matrix3d::Identity(),
                              Eigen::Vector3d::Zero());
  EstimateSample x;
  x.t = 2.0;
  x.v = Eigen::Vector3d(0.5, -0.1, 0);  // r = (0, 0.1, 0)
  BaseCovariance P;
  P.P.setZero();
  P.P.block<3, 3>(0, 0) = Eigen::Matrix3d::Identity() * 0.01;
  const SlipReport with = detector.check(in, x, P);
  CHECK(with.feet[0].S.isApprox(Eigen::Vector3d(0.0025, 0.005, 0.005).asDiagonal().toDenseMatrix(),
                                1e-12));
  CHECK(with.feet[0].d2 == Approx(2.0));  // 0.01 / 0.005
  P.has_attitude = false;                 // a filter without attitude: the v block only
  detector.reset();
  CHECK(detector.check(in, x, P).feet[0].d2 == Approx(4.0));  // 0.01 / 0.0025
}

TEST_CASE("H's attitude block and sign: d2 is chi2_3 when the error is drawn from P",
          "[57.7][slip]") {
  // The truth differs from the estimate by e ~ N(0, P) with strong attitude-velocity correlation,
  // R = Exp(dtheta) R_hat, v = v_hat + dv, and the foot holds in the truth. Kinematic noise ~ 0:
  // the residual is H e, and with the right H its d2 has chi2_3's mean 3 and tail 1 %.
  SlipParams params = instant();
  params.gyro_sigma = 0.0;
  params.foot_velocity_sigma = 1e-5;
  SlipDetector detector(params);
  std::mt19937 rng(7);
  std::normal_distribution<double> n01;
  Eigen::Matrix<double, 9, 9> L = Eigen::Matrix<double, 9, 9>::Zero();
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j <= i; ++j) L(i, j) = (i == j ? 1.0 : 0.8) * (0.5 + 0.5 * std::sin(i + 3 * j));
  }
  L.topRows<3>() *= 0.02;      // attitude: ~ 0.02 rad
  L.middleRows<3>(3) *= 0.02;  // velocity: ~ 0.02 m/s
  BaseCovariance P;
  P.P = L * L.transpose();
  const Eigen::Matrix3d R_hat = lie::SO3d::Exp(Eigen::Vector3d(0.1, -0.2, 0.7)).matrix();
  const Eigen::Vector3d v_hat(0.9, -0.4, 0.2), w(0.3, -0.5, 0.8);
  double sum = 0.0, sum_flipped = 0.0;
  int above = 0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    Eigen::Matrix<double, 9, 1> z;
    for (int i = 0; i < 9; ++i) z(i) = n01(rng);
    const Eigen::Matrix<double, 9, 1> e = L * z;
    const Eigen::Matrix3d R = lie::SO3d::Exp(e.head<3>()).matrix() * R_hat;
    const Eigen::Vector3d v = v_hat + e.segment<3>(3);
    StepInput in;
    in.t = 0.5;
    in.imu.w_m = w;
    in.num_contacts = 1;
    in.contacts[0] = footGiving(1, kFeet[1], v, R, w);  // holds in the truth: v_leg(R) = v
    EstimateSample x;
    x.t = 0.5;
    x.q = Eigen::Quaterniond(R_hat);
    x.v = v_hat;
    detector.reset();
    const FootSlip f = detector.check(in, x, P).feet[0];
    sum += f.d2;
    above += f.slipping ? 1 : 0;
    // The same S with the cross term's sign flipped (the classic error): not chi2_3.
    const Eigen::Matrix3d A = lie::hat3(f.v_leg), P_tv = P.P.block<3, 3>(0, 3);
    const Eigen::Matrix3d flipped = f.S - 2.0 * (A * P_tv + P_tv.transpose() * A.transpose());
    sum_flipped += f.residual.dot(flipped.ldlt().solve(f.residual));
  }
  CHECK(sum / n == Approx(3.0).margin(0.2));
  CHECK(above <= 0.02 * n);
  CHECK(std::abs(sum_flipped / n - 3.0) > 0.5);
}

TEST_CASE("four feet: the one slipping foot is the outlier", "[57.7][slip]") {
  SlipDetector detector(instant());
  EstimateSample x;
  x.t = 0.0;
  x.v = Eigen::Vector3d(0.5, 0, 0);
  const SlipReport ok = detector.check(fourFeet(0.0, x.v), x, velocityOnly(0.02));
  CHECK(ok.num_feet == 4);
  CHECK(ok.outlier == -1);
  CHECK(ok.inconsistent_pairs == 0);
  CHECK(ok.numSlipping() == 0);
  CHECK_FALSE(ok.all_slipping);

  // Foot 2 slides at 0.3 m/s: it disagrees with the three others (3 pairs), they agree.
  const SlipReport one =
      detector.check(fourFeet(0.001, x.v, 2, Eigen::Vector3d(0.3, 0.1, 0)), x, velocityOnly(0.02));
  CHECK(one.outlier == 2);
  CHECK(one.inconsistent_pairs == 3);
  CHECK(one.slipping(2));
  CHECK(one.numSlipping() == 1);
  CHECK_FALSE(one.all_slipping);

  // The outlier test alone names it, even with a filter too uncertain for the per-foot test.
  const SlipReport vague =
      detector.check(fourFeet(0.002, x.v, 1, Eigen::Vector3d(0, 0.4, 0)), x, velocityOnly(1.0));
  CHECK(vague.feet[1].d2 < vague.threshold);
  CHECK(vague.outlier == 1);
  CHECK(vague.slipping(1));

  // Two feet that each disagree with everything: no single outlier.
  StepInput two = fourFeet(0.003, x.v, 0, Eigen::Vector3d(0.3, 0, 0));
  two.contacts[3] = footGiving(3, kFeet[3], Eigen::Vector3d(0.5, -0.4, 0),
                               Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  CHECK(detector.check(two, x, velocityOnly(1.0)).outlier == -1);
  // Three feet, two of them sliding together: the one that holds is not outvoted.
  StepInput together = fourFeet(0.0035, x.v, 0, Eigen::Vector3d(0, 0.5, 0));
  together.contacts[1] = footGiving(1, kFeet[1], x.v + Eigen::Vector3d(0, 0.5, 0),
                                    Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  together.num_contacts = 3;
  const SlipReport majority = detector.check(together, x, velocityOnly(0.02));
  CHECK(majority.outlier == -1);
  CHECK(majority.slipping(0));
  CHECK(majority.slipping(1));
  CHECK_FALSE(majority.slipping(2));
  // Two stance feet (a trot): a disagreement cannot name the foot.
  StepInput pair = fourFeet(0.004, x.v, 0, Eigen::Vector3d(0.3, 0, 0));
  pair.num_contacts = 2;
  const SlipReport trot = detector.check(pair, x, velocityOnly(1.0));
  CHECK(trot.inconsistent_pairs == 1);
  CHECK(trot.outlier == -1);
}

TEST_CASE("a foot slips after confirm_samples exceeded checks in a row", "[57.7][slip]") {
  SlipDetector detector;  // confirm_samples = 3
  REQUIRE(detector.params().confirm_samples == 3);
  EstimateSample x;
  x.v = Eigen::Vector3d(0.5, 0, 0);
  const BaseCovariance P = velocityOnly(0.02);
  const Eigen::Vector3d slide(0, 0.5, 0);
  std::array<bool, 7> slipping{}, exceeds{};
  // Foot 1 slides at checks 0, 1, 2, 3, holds at 4, slides at 5, 6.
  for (int k = 0; k < 7; ++k) {
    x.t = 0.001 * k;
    const SlipReport r = detector.check(fourFeet(x.t, x.v, k == 4 ? -1 : 1, slide), x, P);
    slipping[k] = r.slipping(1);
    exceeds[k] = r.feet[1].exceeds;
    CHECK_FALSE(r.slipping(0));
  }
  CHECK(exceeds == std::array<bool, 7>{true, true, true, true, false, true, true});
  CHECK(slipping == std::array<bool, 7>{false, false, true, true, false, false, false});
  CHECK_THROWS_AS(SlipDetector([] {
                    SlipParams p;
                    p.confirm_samples = 0;
                    return p;
                  }()),
                  std::invalid_argument);
}

TEST_CASE("all feet slipping: the IMU disagrees with the legs (57.7.2)", "[57.7][slip]") {
  // Standing on ice, pushed sideways from t = 1 s: the body accelerates at 2 m/s^2 (the IMU feels
  // it) while every foot slides with the body, so the legs all say v = 0 and agree with each
  // other; the filter that trusts them stays at v = 0 too.
  SlipDetector detector;
  EstimateSample x;  // follows the legs: v = 0
  const BaseCovariance P = velocityOnly(0.01);
  double first = -1.0;
  for (int k = 0; k <= 1500; ++k) {
    const double t = 0.001 * k;
    StepInput in = fourFeet(t, Eigen::Vector3d::Zero());
    if (t >= 1.0) in.imu.a_m.y() += 2.0;
    x.t = t - 0.001;
    const SlipReport r = detector.check(in, x, P);
    CHECK(r.numSlipping() == 0);  // no foot is an outlier: they all agree
    CHECK(r.outlier == -1);
    if (r.all_slipping && first < 0.0) first = t;
  }
  // Quiet before the push; seen within 0.15 s (the legs' 2 m/s^2 * 0.15 s = 0.3 m/s miss).
  CHECK(first >= 1.0);
  CHECK(first < 1.15);

  // The same acceleration seen by the legs too (a real motion): never all slipping.
  detector.reset();
  double v = 0.0;
  bool any = false;
  for (int k = 0; k <= 1500; ++k) {
    const double t = 0.001 * k;
    StepInput in = fourFeet(t, Eigen::Vector3d(0, v, 0));
    if (t >= 1.0) in.imu.a_m.y() += 2.0;
    x.t = t - 0.001;
    x.v = Eigen::Vector3d(0, v, 0);
    any = any || detector.check(in, x, P).all_slipping;
    if (t >= 1.0) v += 2.0 * 0.001;
  }
  CHECK_FALSE(any);
}

TEST_CASE("a common slide slower than the IMU window can show is not seen (57.7.2's limit)",
          "[57.7][slip]") {
  // With the defaults the all-feet test needs |v_c - v_imu| above about
  // sqrt(11.345 (R_i + P_vv + ...)) = 0.19 m/s per axis (R_i = 0.05^2, P_vv = 0.01^2 here), and
  // the anchor is renewed every 0.25 s while nothing exceeds: a slide that gains less than 0.19 m/s
  // in 0.25 s (about 0.75 m/s^2) stays hidden; 1 m/s^2 is seen.
  const BaseCovariance P = velocityOnly(0.01);
  for (const double a : {0.4, 1.0}) {
    SlipDetector detector;
    EstimateSample x;  // follows the legs, which slide with the body: v = 0
    bool seen = false;
    for (int k = 0; k <= 2500; ++k) {
      const double t = 0.001 * k;
      StepInput in = fourFeet(t, Eigen::Vector3d::Zero());
      if (t >= 1.0) in.imu.a_m.y() += a;
      x.t = t - 0.001;
      seen = seen || detector.check(in, x, P).imu_disagrees;
    }
    INFO("a = " << a << " m/s^2");
    CHECK(seen == (a > 0.75));
  }
}

TEST_CASE("the slip check, the guard and the plane fit never allocate", "[57.7][slip]") {
  SlipGuard guard(SlipParams{}, SlipReaction::kImuOnly);
  TerrainClassifier terrain;
  const std::optional<BaseCovariance> P = velocityOnly(0.02);
  std::optional<StepInput> storage;
  SlipReport report;
  EstimateSample x;
  x.v = Eigen::Vector3d(0.5, 0, 0);
  const std::array<Eigen::Vector3d, 4> forces = {
      Eigen::Vector3d(10, 0, 100), Eigen::Vector3d(10, 0, 100), Eigen::Vector3d(10, 0, 100),
      Eigen::Vector3d(10, 0, 100)};
  std::vector<StepInput> inputs;
  for (int k = 0; k < 100; ++k) {
    inputs.push_back(fourFeet(0.001 * k, x.v, k % 10 < 5 ? 2 : -1, Eigen::Vector3d(0.4, 0, 0)));
  }
  const long before = legkit::test::allocationCount();
  int dropped = 0;
  for (const StepInput& in : inputs) {
    x.t = in.t - 0.001;
    dropped += 4 - guard.apply(in, x, P, storage, &report).num_contacts;
    terrain.update(report, forces.data(), 4, 0.001);
    dropped += fitGroundPlane(kFeet.data(), 4).status == GroundPlane::kOk ? 0 : 1000;
  }
  CHECK(legkit::test::allocationCount() == before);
  CHECK(dropped > 0);
  CHECK(dropped < 1000);
}

TEST_CASE("reactions on the filter's input", "[57.7][slip]") {
  CHECK(slipReactionByName("none") == SlipReaction::kNone);
  CHECK(slipReactionByName("inflate") == SlipReaction::kInflate);
  CHECK(slipReactionByName("drop") == SlipReaction::kDrop);
  CHECK(slipReactionByName("imu-only") == SlipReaction::kImuOnly);
  CHECK_FALSE(slipReactionByName("ignore"));
  CHECK(std::string(slipReactionName(SlipReaction::kImuOnly)) == "imu-only");

  EstimateSample x;
  x.v = Eigen::Vector3d(0.5, 0, 0);
  const StepInput quiet = fourFeet(0.0, x.v);
  const StepInput one = fourFeet(0.0, x.v, 2, Eigen::Vector3d(0.4, 0, 0));
  const std::optional<BaseCovariance> P = velocityOnly(0.02);

  for (const SlipReaction reaction :
       {SlipReaction::kNone, SlipReaction::kInflate, SlipReaction::kDrop, SlipReaction::kImuOnly}) {
    SlipGuard guard(instant(), reaction);
    std::optional<StepInput> storage;
    SlipReport report;
    // Nothing slips: the input itself, no copy.
    CHECK(&guard.apply(quiet, x, P, storage, &report) == &quiet);
    CHECK_FALSE(storage);
    CHECK_FALSE(quiet.slip);
    guard.reset();
    const StepInput& out = guard.apply(one, x, P, storage, &report);
    CHECK(report.slipping(2));
    if (reaction == SlipReaction::kNone) {
      CHECK(&out == &one);
      CHECK_FALSE(out.slip);
      continue;
    }
    REQUIRE(storage);
    CHECK(&out == &*storage);
    CHECK(out.slip);  // a reaction tells the filters (their heading rule holds whole)
    if (reaction == SlipReaction::kInflate) {
      REQUIRE(out.num_contacts == 4);
      CHECK(out.contacts[2].cov.isApprox(one.contacts[2].cov * 100.0));
      CHECK(out.contacts[1].cov == one.contacts[1].cov);
    } else {  // kDrop and kImuOnly: a single slipping foot is dropped
      REQUIRE(out.num_contacts == 3);
      CHECK(out.contacts[0].foot == 0);
      CHECK(out.contacts[1].foot == 1);
      CHECK(out.contacts[2].foot == 3);
      CHECK(out.normal_force[2] == one.normal_force[3]);
    }
  }

  // Every foot slipping (one foot, far off the estimate): kDrop and kImuOnly drop it.
  StepInput single = quiet;
  single.num_contacts = 1;
  EstimateSample still;
  for (const SlipReaction reaction : {SlipReaction::kDrop, SlipReaction::kImuOnly}) {
    SlipGuard guard(instant(), reaction);
    std::optional<StepInput> storage;
    SlipReport report;
    CHECK(guard.apply(single, still, P, storage, &report).num_contacts == 0);
    CHECK(report.all_slipping);
  }
}

TEST_CASE("imu-only drops every foot while the IMU says all slip; drop keeps them",
          "[57.7][slip]") {
  const BaseCovariance P = velocityOnly(0.01);
  SlipGuard imu_only(SlipParams{}, SlipReaction::kImuOnly), drop(SlipParams{}, SlipReaction::kDrop);
  EstimateSample x;
  int imu_only_feet = -1, drop_feet = -1;
  for (int k = 0; k <= 1300; ++k) {
    const double t = 0.001 * k;
    StepInput in = fourFeet(t, Eigen::Vector3d::Zero());
    if (t >= 1.0) in.imu.a_m.y() += 2.0;
    x.t = t - 0.001;
    std::optional<StepInput> s1, s2;
    SlipReport report;
    imu_only_feet = imu_only.apply(in, x, P, s1, &report).num_contacts;
    drop_feet = drop.apply(in, x, P, s2).num_contacts;
    if (k == 1300) CHECK(report.all_slipping);
  }
  CHECK(imu_only_feet == 0);
  CHECK(drop_feet == 4);
}

TEST_CASE("ground plane: exact plane, least squares and degenerate footholds", "[57.7][terrain]") {
  // Exact: z = 1 + 0.5 x - 0.2 y through four feet.
  const std::array<Eigen::Vector3d, 4> exact = {
      Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 1.5), Eigen::Vector3d(0, 1, 0.8),
      Eigen::Vector3d(1, 1, 1.3)};
  GroundPlane g = fitGroundPlane(exact.data(), 4);
  REQUIRE(g.status == GroundPlane::kOk);
  CHECK(g.a == Approx(1.0));
  CHECK(g.b == Approx(0.5));
  CHECK(g.c == Approx(-0.2));
  CHECK(g.slope == Approx(std::atan(std::sqrt(0.29))));
  CHECK(g.normal.isApprox(Eigen::Vector3d(-0.5, 0.2, 1.0).normalized()));
  CHECK(g.rms == Approx(0.0).margin(1e-12));
  CHECK(g.height(2.0, 1.0) == Approx(1.8));
  CHECK(g.spread == Approx(0.5));

  // Least squares: three corners at 0, the fourth at 0.4: a = -0.1, b = c = 0.2, residuals 0.1.
  const std::array<Eigen::Vector3d, 4> ls = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                             Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 1, 0.4)};
  g = fitGroundPlane(ls.data(), 4);
  REQUIRE(g.status == GroundPlane::kOk);
  CHECK(g.a == Approx(-0.1));
  CHECK(g.b == Approx(0.2));
  CHECK(g.c == Approx(0.2));
  CHECK(g.rms == Approx(0.1));

  // Three feet: exactly determined.
  CHECK(fitGroundPlane(exact.data(), 3).status == GroundPlane::kOk);
  CHECK(fitGroundPlane(exact.data(), 3).b == Approx(0.5));
  // Fewer than three: the mean height, flat.
  g = fitGroundPlane(exact.data(), 2);
  CHECK(g.status == GroundPlane::kTooFewFeet);
  CHECK(g.a == Approx(1.25));
  CHECK(g.slope == 0.0);
  CHECK(fitGroundPlane(nullptr, 0).status == GroundPlane::kTooFewFeet);
  // Collinear (x, y): on the diagonal, and within 1 cm of a line.
  const std::array<Eigen::Vector3d, 3> line = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 0.1),
                                               Eigen::Vector3d(2, 2, 0.3)};
  CHECK(fitGroundPlane(line.data(), 3).status == GroundPlane::kCollinear);
  const std::array<Eigen::Vector3d, 3> almost = {
      Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.3, 0.01, 0), Eigen::Vector3d(0.6, 0, 0)};
  g = fitGroundPlane(almost.data(), 3);
  CHECK(g.status == GroundPlane::kCollinear);
  CHECK(g.spread < 0.01);
  CHECK(fitGroundPlane(almost.data(), 3, 0.001).status == GroundPlane::kOk);
  // Bad input.
  std::array<Eigen::Vector3d, 3> bad = line;
  bad[1].x() = std::nan("");
  CHECK_THROWS_AS(fitGroundPlane(bad.data(), 3), std::invalid_argument);
  CHECK_THROWS_AS(fitGroundPlane(nullptr, 3), std::invalid_argument);
}

namespace {

// A number in [lo, hi] on a grid of 2001 values (RapidCheck shrinks it towards lo).
double genIn(double lo, double hi) {
  return lo + (hi - lo) * (*rc::gen::inRange(0, 2001)) / 2000.0;
}

}  // namespace

TEST_CASE("ground plane: any plane through 3..8 spread footholds is recovered", "[57.7][terrain]") {
  rc::prop("exact plane", [] {
    const double a = genIn(-1.0, 1.0), b = genIn(-0.3, 0.3), c = genIn(-0.3, 0.3);
    const int n = *rc::gen::inRange(3, 9);
    std::array<Eigen::Vector3d, 8> feet{};
    // Feet on a circle of radius 0.3 m (spread >= 0.3 / 2 for 3 or more equally spaced points),
    // turned and shifted at random.
    const double turn = genIn(0.0, 6.283), x0 = genIn(-5.0, 5.0), y0 = genIn(-5.0, 5.0);
    for (int i = 0; i < n; ++i) {
      const double angle = turn + 6.283185307179586 * i / n;
      const double x = x0 + 0.3 * std::cos(angle), y = y0 + 0.3 * std::sin(angle);
      feet[i] = Eigen::Vector3d(x, y, a + b * x + c * y);
    }
    const GroundPlane g = fitGroundPlane(feet.data(), n);
    RC_ASSERT(g.status == GroundPlane::kOk);
    RC_ASSERT(std::abs(g.a - a) < 1e-9);
    RC_ASSERT(std::abs(g.b - b) < 1e-9);
    RC_ASSERT(std::abs(g.c - c) < 1e-9);
    RC_ASSERT(g.rms < 1e-9);
    RC_ASSERT(std::abs(g.normal.dot(Eigen::Vector3d(1.0, 0.0, b))) < 1e-9);  // normal to the plane
  });
}

TEST_CASE("drop keeps exactly the feet that do not slip, in order", "[57.7][slip]") {
  rc::prop("drop", [] {
    const int n = *rc::gen::inRange(1, 9);
    const int slipping_mask = *rc::gen::inRange(0, 1 << n);
    EstimateSample x;
    x.v = Eigen::Vector3d(0.4, 0.0, 0.0);
    StepInput in;
    for (int i = 0; i < n; ++i) {
      const bool slips = (slipping_mask >> i) & 1;
      const Eigen::Vector3d p(0.2 * (i % 2 ? 1 : -1), 0.05 * i, -0.3);
      in.contacts[i] = footGiving(7 - i, p, x.v + Eigen::Vector3d(0.0, slips ? 0.5 : 0.0, 0.0),
                                  Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
      in.normal_force[i] = 10.0 * i;
    }
    in.num_contacts = n;
    SlipGuard guard(instant(), SlipReaction::kDrop);
    std::optional<StepInput> storage;
    SlipReport report;
    const StepInput& out = guard.apply(in, x, velocityOnly(0.02), storage, &report);
    int k = 0;
    for (int i = 0; i < n; ++i) {
      RC_ASSERT(report.slipping(7 - i) == bool((slipping_mask >> i) & 1));
      if ((slipping_mask >> i) & 1) continue;
      RC_ASSERT(out.contacts[k].foot == 7 - i);
      RC_ASSERT(out.normal_force[k] == in.normal_force[i]);
      ++k;
    }
    RC_ASSERT(out.num_contacts == k);
    RC_ASSERT((slipping_mask == 0) == (&out == &in));
  });
}

namespace {

// One foot (id 0) in stance with the given slip flag.
SlipReport stance(bool slipping) {
  SlipReport r;
  r.num_feet = 1;
  r.feet[0].foot = 0;
  r.feet[0].slipping = slipping;
  return r;
}

// A stream of `steps` samples of `period` each: stance at |f_t| / f_n = ratio (f_n = 100 N),
// one slip onset every `slip_every` samples (0: never).
TerrainClassifier stream(double ratio, int steps, int slip_every) {
  TerrainClassifier c;
  const std::array<Eigen::Vector3d, 1> f = {Eigen::Vector3d(ratio * 60.0, ratio * 80.0, 100.0)};
  for (int k = 0; k < steps; ++k) {
    const bool slip = slip_every > 0 && k % slip_every == slip_every - 1;
    c.update(stance(slip), f.data(), 1, 0.01);
  }
  return c;
}

}  // namespace

TEST_CASE("terrain classes from force and slip streams", "[57.7][terrain]") {
  CHECK(std::string(terrainClassName(TerrainClass::kHighGrip)) == "high-grip");
  // Ice: slips at |f_t| / f_n = 0.1.
  TerrainClassifier ice = stream(0.1, 100, 10);
  CHECK(ice.terrain() == TerrainClass::kIce);
  CHECK(ice.frictionEstimate() == Approx(0.1));
  CHECK(ice.onsets() == 10);
  CHECK(ice.slipRate() == Approx(10.0));  // 10 onsets in 1 s of stance
  CHECK(ice.slipFraction() == Approx(0.1));
  // Two onsets are not yet enough evidence.
  CHECK(stream(0.1, 20, 10).terrain() == TerrainClass::kUnknown);
  // Normal: slips at 0.5.
  TerrainClassifier normal = stream(0.5, 100, 10);
  CHECK(normal.terrain() == TerrainClass::kNormal);
  CHECK(normal.frictionEstimate() == Approx(0.5));
  // High grip from onsets at 1.0, and from holding at 0.95 without a slip.
  CHECK(stream(1.0, 100, 10).terrain() == TerrainClass::kHighGrip);
  TerrainClassifier grip = stream(0.95, 10, 0);
  CHECK(grip.terrain() == TerrainClass::kHighGrip);
  CHECK(grip.frictionLowerBound() == Approx(0.95));
  CHECK(std::isnan(grip.frictionEstimate()));
  // Holding at 0.4 without slips: unknown for less than 2 s of stance, then normal.
  CHECK(stream(0.4, 150, 0).terrain() == TerrainClass::kUnknown);
  CHECK(stream(0.4, 250, 0).terrain() == TerrainClass::kNormal);
  // Standing (no tangential force) proves nothing.
  CHECK(stream(0.0, 500, 0).terrain() == TerrainClass::kUnknown);

  // A light foot and a missing force give no friction sample; an onset still counts as a slip.
  TerrainClassifier c;
  const std::array<Eigen::Vector3d, 1> light = {Eigen::Vector3d(1.0, 0.0, 5.0)};
  const std::array<Eigen::Vector3d, 1> none = {Eigen::Vector3d::Constant(std::nan(""))};
  c.update(stance(true), light.data(), 1, 0.01);
  c.update(stance(false), none.data(), 1, 0.01);
  c.update(stance(true), none.data(), 1, 0.01);
  CHECK(c.onsets() == 0);
  CHECK(c.slipRate() == Approx(2.0 / 0.03));
  CHECK(c.frictionLowerBound() == 0.0);
  c.reset();
  CHECK(c.stanceTime() == 0.0);
  CHECK_THROWS_AS(TerrainClassifier(TerrainParams{0.5, 0.3}), std::invalid_argument);

  // On a slope the forces split along the ground's normal: a force along it has no f_t.
  TerrainClassifier slope;
  const Eigen::Vector3d n = Eigen::Vector3d(-0.3, 0.0, 1.0).normalized();
  slope.setGroundNormal(n);
  const std::array<Eigen::Vector3d, 1> along = {Eigen::Vector3d(100.0 * n)};
  slope.update(stance(false), along.data(), 1, 0.01);
  CHECK(slope.frictionLowerBound() == Approx(0.0).margin(1e-12));
  const std::array<Eigen::Vector3d, 1> level = {Eigen::Vector3d(0.0, 0.0, 100.0)};
  slope.update(stance(false), level.data(), 1, 0.01);
  CHECK(slope.frictionLowerBound() == Approx(0.3));  // tan of the slope angle
}
