// Flat feet in the ESKF, the InEKF and the TSIF (section 57.5; the "Flat feet" paragraphs of
// estimation/invariant/eskf.hpp, invariant_ekf.hpp and tsif.hpp) on a simulated biped: feet 0 and 1
// of the trot, which stand in turn as a walking biped's do. Each is given a sole whose world
// orientation R_F stays fixed from its touchdown to its lift-off, measured through the body as a
// robot's kinematics would: Z = R^T R_F Exp(n), n ~ N(0, sigma^2 I).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "allocation_counter.hpp"
#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/invariant/tsif.hpp"
#include "eval/consistency.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "filter_family.hpp"
#include "trot_log.hpp"

using namespace legkit;
using legkit::test::normal3;

namespace {

constexpr double kSoleSigma = 0.002;  // [rad] the soles' measurement noise in these runs

struct Biped {
  std::vector<EstimateSample> truth;  // per row
  std::vector<StepInput> inputs;      // feet 0 and 1 only, each with its sole's orientation
  std::vector<std::array<std::optional<lie::SO3d>, 2>> sole;  // per row: R_F of a foot down
};

// `duration` s of the trot from `seed` with the biases `bias`, as the biped above.
Biped bipedRun(unsigned seed, const model::ImuBias& bias, double duration = 5.0) {
  const io::Log log = test::trotLog(duration, seed, false, bias);
  const std::vector<StepInput> all = test::inputsOf(log, test::simulatorFrontend());
  std::mt19937 gen(seed + 77);
  // Each foot's sole sits turned against the body by a fixed rotation, as a real ankle's does.
  const std::array<lie::SO3d, 2> mount = {lie::SO3d::Exp(Eigen::Vector3d(0.05, -0.1, 0.3)),
                                          lie::SO3d::Exp(Eigen::Vector3d(-0.04, 0.08, -0.25))};
  Biped b;
  std::array<std::optional<lie::SO3d>, 2> down{};
  for (std::size_t k = 0; k < all.size(); ++k) {
    const io::LogRow& row = log.rows[k];
    b.truth.push_back({row.t, row.gt_q, row.gt_v, row.gt_p});
    const lie::SO3d R = lie::SO3d::fromQuaternion(row.gt_q);
    StepInput in = all[k];
    in.num_contacts = 0;
    std::array<std::optional<lie::SO3d>, 2> now{};
    for (const ContactMeasurement& c : all[k].stance()) {
      if (c.foot > 1) continue;
      // R_F is placed at the touchdown and stays while the foot is down.
      now[c.foot] = down[c.foot] ? *down[c.foot] : R * mount[c.foot];
      ContactMeasurement m = c;
      const Eigen::Matrix3d Z = R.matrix().transpose() * now[c.foot]->matrix();
      m.R_body = Z * lie::SO3d::Exp(normal3(gen, kSoleSigma)).matrix();
      m.rot_cov = kSoleSigma * kSoleSigma * Eigen::Matrix3d::Identity();
      in.contacts[in.num_contacts++] = m;
    }
    down = now;
    b.sole.push_back(now);
    b.inputs.push_back(in);
  }
  return b;
}

// What the tests read of each filter, each in its own error convention: a held sole's error and
// its block of P, and the gyro bias about the body's z with its standard deviation.
struct SoleError {
  Eigen::Vector3d error;
  Eigen::Matrix3d P;
};

struct EskfFlat {
  using Filter = invariant::Eskf;
  using Params = invariant::EskfParams;
  // R_F = R_F,hat Exp(dphi): local, as the attitude.
  static std::optional<SoleError> sole(const Filter& f, int i, const lie::SO3d& R_F) {
    if (!f.inContact(i)) return std::nullopt;
    const int at = invariant::eskf::rotationIndex(i);
    return SoleError{R_F.rminus(f.footRotation(i)), f.P().block<3, 3>(at, at)};
  }
  static std::pair<double, double> biasZ(const Filter& f) {
    const int z = invariant::eskf::kBg + 2;
    return {f.state().b_g.z(), std::sqrt(f.P()(z, z))};
  }
};

struct InekfFlat {
  using Filter = invariant::InvariantEkf;
  using Params = invariant::InvariantEkfParams;
  // R_F,hat = Exp(phi_F) R_F: right-invariant, beside the group.
  static std::optional<SoleError> sole(const Filter& f, int i, const lie::SO3d& R_F) {
    const int at = f.rotationIndexOf(i);
    if (at < 0) return std::nullopt;
    const Eigen::Matrix3d E = f.footRotation(i) * R_F.matrix().transpose();  // R_F,hat R_F^T
    return SoleError{lie::SO3d::fromQuaternion(Eigen::Quaterniond(E)).Log(),
                     f.P().block<3, 3>(at, at)};
  }
  static std::pair<double, double> biasZ(const Filter& f) {
    const int z = 3 + 3 * static_cast<int>(f.X().numCols()) + 2;  // b_g after xi
    return {f.b_g().z(), std::sqrt(f.P()(z, z))};
  }
};

struct TsifFlat {
  using Filter = invariant::Tsif;
  using Params = invariant::TsifParams;
  // The ESKF's local error, R_F = R_F,hat Exp(dphi), and its block of P.
  static std::optional<SoleError> sole(const Filter& f, int i, const lie::SO3d& R_F) {
    if (!f.inContact(i)) return std::nullopt;
    const int at = invariant::tsif::rotationIndex(i);
    return SoleError{R_F.rminus(f.footRotation(i)), f.P().block<3, 3>(at, at)};
  }
  static std::pair<double, double> biasZ(const Filter& f) {
    const int z = invariant::tsif::kBg + 2;
    return {f.state().b_g.z(), std::sqrt(f.P()(z, z))};
  }
};

template <class Flat>
typename Flat::Params bipedParams(bool flat) {
  typename Flat::Params p;
  p.flat_feet = flat;
  p.foot_stance_density = 1e-4;           // the simulator's feet do not slip
  p.foot_rotation_stance_density = 1e-4;  // nor do these soles turn
  return p;
}

struct Errors {
  std::vector<double> nees;   // per row, 9 dof
  double tilt_rms = 0.0;      // roll and pitch [rad]
  double sole_nees = 0.0;     // mean over the rows of a held sole of its 3-dof NEES
  double bias_z = 0.0;        // the last row's gyro bias estimate about the body's z [rad/s]
  double sigma_bias_z = 0.0;  // and its standard deviation
  double sigma_yaw = 0.0;     // the last row's yaw standard deviation (world z) [rad]
};

// One run from an initial error drawn from the filter's prior (isotropic: the same draw serves a
// local and a world-frame attitude error).
template <class Flat>
Errors run(const Biped& b, const typename Flat::Params& params, unsigned seed) {
  std::mt19937 gen(seed);
  EstimateSample x0 = b.truth.front();
  x0.q = Eigen::Quaterniond(x0.q.toRotationMatrix() *
                            lie::SO3d::Exp(-normal3(gen, params.sigma_attitude)).matrix());
  x0.v -= normal3(gen, params.sigma_velocity);
  x0.p -= normal3(gen, params.sigma_position);
  typename Flat::Filter filter(params);
  filter.reset(x0);
  Errors e;
  double tilt2 = 0.0;
  int sole_rows = 0;
  for (std::size_t k = 0; k < b.inputs.size(); ++k) {
    filter.step(b.inputs[k]);
    const EstimateSample x = filter.estimate();
    e.nees.push_back(eval::nees(b.truth[k], x, *filter.covariance()));
    const double tilt = eval::tiltError(x.q.toRotationMatrix(), b.truth[k].q.toRotationMatrix());
    tilt2 += tilt * tilt;
    if (!params.flat_feet) continue;
    for (int i = 0; i < 2; ++i) {
      // The sole's error against its block of P, once the foot has stood a second sample.
      if (!b.sole[k][i] || k == 0 || !b.sole[k - 1][i]) continue;
      const std::optional<SoleError> sole = Flat::sole(filter, i, *b.sole[k][i]);
      if (!sole) continue;
      e.sole_nees += sole->error.dot(sole->P.ldlt().solve(sole->error));
      ++sole_rows;
    }
  }
  e.tilt_rms = std::sqrt(tilt2 / b.inputs.size());
  std::tie(e.bias_z, e.sigma_bias_z) = Flat::biasZ(filter);
  e.sigma_yaw = std::sqrt(filter.covariance()->P(2, 2));
  if (sole_rows > 0) e.sole_nees /= sole_rows;
  return e;
}

}  // namespace

TEMPLATE_TEST_CASE("Flat feet: the base and the soles stay consistent over a Monte Carlo of runs",
                   "[57.5][eskf][inekf][tsif][flat-feet][study]", EskfFlat, InekfFlat, TsifFlat) {
  constexpr int kRuns = 20;
  const auto params = bipedParams<TestType>(true);
  std::vector<double> anees;
  double sole_nees = 0.0;
  for (int j = 0; j < kRuns; ++j) {
    std::mt19937 gen(500 + j);
    model::ImuBias bias;
    bias.b_g = normal3(gen, params.sigma_gyro_bias);
    bias.b_a = normal3(gen, params.sigma_accel_bias);
    const Errors e = run<TestType>(bipedRun(1 + j, bias), params, 900 + j);
    if (anees.empty()) anees.assign(e.nees.size(), 0.0);
    for (std::size_t k = 0; k < anees.size(); ++k) anees[k] += e.nees[k] / kRuns;
    sole_nees += e.sole_nees / kRuns;
  }
  const eval::ChiSquareBounds bounds = eval::aneesBounds(9, kRuns);
  double mean = 0.0;
  int inside = 0;
  for (const double a : anees) {
    mean += a / anees.size();
    inside += a >= bounds.lower && a <= bounds.upper;
  }
  INFO("base ANEES per dof " << mean / 9 << ", bounds [" << bounds.lower / 9 << ", "
                             << bounds.upper / 9 << "], " << 100.0 * inside / anees.size()
                             << " % of rows inside; the soles' NEES per dof " << sole_nees / 3);
  CHECK(mean >= bounds.lower);
  CHECK(mean <= bounds.upper);
  // The soles' own errors against their block of P: 3 dof, about 1 per dof.
  CHECK(sole_nees / 3 > 0.5);
  CHECK(sole_nees / 3 < 2.0);
}

TEMPLATE_TEST_CASE(
    "Flat feet: the heading rule holds the soles as it holds the positions, and walking straight "
    "the soles learn the gyro bias about the vertical faster than point feet",
    "[57.5][eskf][inekf][tsif][flat-feet][heading][study]", EskfFlat, InekfFlat, TsifFlat) {
  // A turn-on bias of 0.005 rad/s about the body's z (a MEMS gyro's, 0.3 deg/s; 2.5 sigma of
  // the filters' prior). Under the whole heading rule (heading_turn_rate 0, as while the robot
  // turns fast or a foot slips) no foot update, a sole's included, may move the heading or the
  // gyro bias about the vertical: its standard deviation stays the prior's. Walking straight (the
  // default rule, alpha near 0) a standing sole shows the body's rotation against a foot that
  // does not turn, with no leg scale in it, and the filter learns the bias from it and from the
  // positions. Slowly: a stance of 0.2 s sees 1 mrad of it, as much as the gyro's own noise over
  // that time (measured, 5 runs of 5 s, each of the three filters: whole rule 4.99e-3 rad/s of
  // error, sigma 2.00e-3, the prior's; flat feet 3.8e-3 and 1.47e-3; point feet 4.8e-3 and
  // 1.86e-3; the yaw's sigma at the end 0.0167 rad under the whole rule, flat or point feet
  // alike to 2e-4 of it, and 0.011 walking straight with flat feet). Before the soles came under
  // the rule, the whole rule left them 3.3e-3 and 1.4e-3.
  constexpr double kBias = 0.005;
  struct Mean {
    double error = 0.0, sigma = 0.0, tilt = 0.0;  // |b_g,z - kBias|, its sigma, tilt RMS
    double sigma_yaw = 0.0;                       // the yaw's sigma at the end
    void add(const Errors& e, int runs) {
      error += std::abs(e.bias_z - kBias) / runs;
      sigma += e.sigma_bias_z / runs;
      tilt += e.tilt_rms / runs;
      sigma_yaw += e.sigma_yaw / runs;
    }
  };
  Mean flat_whole, point_whole, flat, point;
  constexpr int kRuns = 5;
  for (int j = 0; j < kRuns; ++j) {
    model::ImuBias bias;
    bias.b_g = Eigen::Vector3d(0.0, 0.0, kBias);
    const Biped b = bipedRun(40 + j, bias);
    auto whole_rule = bipedParams<TestType>(true);
    whole_rule.heading_turn_rate = 0.0;
    flat_whole.add(run<TestType>(b, whole_rule, 60 + j), kRuns);
    auto point_whole_rule = bipedParams<TestType>(false);
    point_whole_rule.heading_turn_rate = 0.0;
    point_whole.add(run<TestType>(b, point_whole_rule, 60 + j), kRuns);
    flat.add(run<TestType>(b, bipedParams<TestType>(true), 60 + j), kRuns);
    point.add(run<TestType>(b, bipedParams<TestType>(false), 60 + j), kRuns);
  }
  INFO("gyro bias error about z after 5 s [rad/s] (sigma): flat feet, whole rule "
       << flat_whole.error << " (" << flat_whole.sigma << "); flat feet " << flat.error << " ("
       << flat.sigma << "); point feet " << point.error << " (" << point.sigma << "); tilt RMS "
       << flat.tilt << " / " << point.tilt << " rad; yaw sigma at the end: whole rule, flat "
       << flat_whole.sigma_yaw << " / point " << point_whole.sigma_yaw << ", default rule, flat "
       << flat.sigma_yaw << " rad");
  const double prior = bipedParams<TestType>(true).sigma_gyro_bias;
  CHECK(flat_whole.sigma > 0.99 * prior);
  CHECK(flat_whole.error > 0.9 * kBias);
  // Nor the heading: its sigma ends where the point feet's ends under the whole rule (which no
  // update reduces), where walking straight the soles take it a third lower.
  CHECK(std::abs(flat_whole.sigma_yaw / point_whole.sigma_yaw - 1.0) < 1e-3);
  CHECK(flat.sigma_yaw < 0.8 * flat_whole.sigma_yaw);
  CHECK(flat.error < 0.9 * point.error);
  CHECK(flat.sigma < 0.9 * point.sigma);
  CHECK(flat.tilt < point.tilt);
}

TEMPLATE_TEST_CASE("Flat feet: no heap allocation per step, through touchdowns and lift-offs",
                   "[57.5][eskf][inekf][tsif][flat-feet]", EskfFlat, InekfFlat, TsifFlat) {
  const Biped b = bipedRun(5, model::ImuBias{}, 2.0);
  int changes = 0;  // touchdowns and lift-offs
  for (std::size_t k = 1; k < b.sole.size(); ++k) {
    for (int i = 0; i < 2; ++i) changes += b.sole[k][i].has_value() != b.sole[k - 1][i].has_value();
  }
  REQUIRE(changes >= 4);  // each sole lands and lifts in these 2 s
  typename TestType::Filter filter(bipedParams<TestType>(true));  // built before counting
  const long before = test::allocationCount();
  filter.reset(b.truth.front());
  for (const StepInput& in : b.inputs) filter.step(in);
  CHECK(test::allocationCount() - before == 0);
  CHECK(filter.estimate().t == b.inputs.back().t);  // it did run
  CHECK(filter.health().healthy());
}

TEST_CASE("Flat feet: a third foot has no slot, a sole that is no rotation is refused",
          "[57.5][eskf][flat-feet]") {
  const Biped b = bipedRun(3, model::ImuBias{}, 1.5);
  invariant::Eskf filter(bipedParams<EskfFlat>(true));
  filter.reset(b.truth.front());
  std::size_t k = 0;
  for (; k + 1 < b.inputs.size() && b.inputs[k].num_contacts < 1; ++k) filter.step(b.inputs[k]);
  StepInput in = b.inputs[k];
  REQUIRE(in.num_contacts >= 1);

  StepInput spoiled = in;
  spoiled.contacts[0].R_body = 1.1 * *in.contacts[0].R_body;
  CHECK_THROWS_WITH(filter.step(spoiled),
                    Catch::Contains("orientation R_body is not a rotation matrix"));
  spoiled = in;
  spoiled.contacts[0].rot_cov(0, 0) = -1.0;
  CHECK_THROWS_WITH(filter.step(spoiled),
                    Catch::Contains("orientation covariance is not positive definite"));

  // A quadruped's third foot: two flat feet fill the filter; the third is left out, and said.
  StepInput three = in;
  for (int foot = 0; foot < 3; ++foot) {
    if (foot < three.num_contacts) {
      three.contacts[foot].foot = foot;
    } else {
      three.contacts[three.num_contacts] = three.contacts[0];
      three.contacts[three.num_contacts++].foot = foot;
    }
  }
  filter.step(three);
  CHECK(filter.health()[Fault::kNoFootSlot] > 0);
}

TEST_CASE("Flat feet need a model of the robot's feet: points are refused by the front end",
          "[57.5][flat-feet]") {
  const io::Log log = test::trotLog(0.2, 1, true);
  FrontendNoise noise;
  noise.foot_rotations = true;
  CHECK_THROWS_WITH(LogFrontend(log.layout, model::QuadrupedKinematics(), noise),
                    Catch::Contains("feet.flat"));
}
