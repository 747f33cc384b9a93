// The right-invariant EKF (section 57.5): its Phi blocks against lie::imu::phiWithBias and the
// reference's I + A dt, one whole step against the dense textbook formulas (both
// discretisations), contacts added and removed, the update along H, the covariance mapping,
// dead reckoning against lie::imu::propagate, bad input, Monte Carlo
// NEES on the simulated trot, and the reference's Cassie log (reader, whole run, and the
// reference implementation's own states on it).
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <sstream>

#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/consistency.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "filter_family.hpp"
#include "io/hartley_log.hpp"
#include "io/log_error.hpp"
#include "lie/imu_dynamics.hpp"
#include "sim/simulator.hpp"
#include "trot_log.hpp"

using namespace legkit;
using namespace legkit::invariant;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using inekf::Discretisation;
using inekf::Group;
using legkit::test::checkFamilyParamsRefused;
using legkit::test::checkStepFaultsRefused;
using legkit::test::inputsOf;
using legkit::test::monteCarloNees;
using legkit::test::NeesResult;
using legkit::test::normal3;
using legkit::test::simulatorFrontend;
using legkit::test::stepToTwoFeet;
using legkit::test::trotLog;
constexpr auto kWorld = legkit::test::AttitudeError::kWorld;

namespace {

const Vector3d kGravity = model::gravity();

Group randomGroup(std::mt19937& gen, int columns) {
  Group::Columns C(3, columns);
  for (int i = 0; i < columns; ++i) C.col(i) = normal3(gen, 2.0);
  return Group(lie::SO3d::Random(gen), C);
}

ContactMeasurement foothold(int foot, const Vector3d& p_body, double sigma) {
  ContactMeasurement c;
  c.foot = foot;
  c.p_body = p_body;
  c.cov = sigma * sigma * Matrix3d::Identity();
  c.cov(0, 1) = c.cov(1, 0) = 0.3 * sigma * sigma;  // not diagonal: R_hat Cov R_hat^T matters
  return c;
}

StepInput input(double t, double dt, const model::ImuReading& imu,
                const std::vector<ContactMeasurement>& contacts) {
  StepInput in;
  in.t = t;
  in.dt = dt;
  in.imu = imu;
  for (const ContactMeasurement& c : contacts) in.contacts[in.num_contacts++] = c;
  return in;
}

double maxAbs(const MatrixXd& M) {
  return M.cwiseAbs().maxCoeff();
}

double minEigenvalue(const MatrixXd& P) {
  return Eigen::SelfAdjointEigenSolver<MatrixXd>(P).eigenvalues().minCoeff();
}

// A_full dt of the reference (first order, bias columns at the state before the step).
MatrixXd referencePhi(const Group& X, double dt) {
  const int nav = static_cast<int>(X.dof());
  MatrixXd A = MatrixXd::Zero(nav + 6, nav + 6);
  A.block<3, 3>(3, 0) = lie::hat3(kGravity);
  A.block<3, 3>(6, 3) = Matrix3d::Identity();
  A.block<3, 3>(0, nav) = -X.R();
  A.block<3, 3>(3, nav + 3) = -X.R();
  for (int i = 0; i < X.numCols(); ++i) {
    A.block<3, 3>(3 + 3 * i, nav) = -lie::hat3(Vector3d(X.col(i))) * X.R();
  }
  return MatrixXd::Identity(nav + 6, nav + 6) + A * dt;
}

}  // namespace

TEST_CASE("InEKF: Phi's blocks are lie::imu::phiWithBias (exact) and I + A dt (first order)",
          "[57.5][inekf]") {
  std::mt19937 gen(11);
  for (int feet = 0; feet <= inekf::kMaxFeet; ++feet) {
    for (const double dt : {1e-3, 0.02}) {
      CAPTURE(feet, dt);
      const Group X = randomGroup(gen, 2 + feet);
      const Vector3d w = normal3(gen, 1.5), a = normal3(gen, 5.0);
      const Group X_exact = inekf::propagateMean(X, w, a, kGravity, dt, Discretisation::kExact);
      CHECK(X_exact.isApprox(lie::imu::propagate(X, w, a, kGravity, dt), 1e-15));
      const MatrixXd exact =
          inekf::transition(X, X_exact, w, a, kGravity, dt, Discretisation::kExact).matrix();
      const MatrixXd expected = lie::imu::phiWithBias(X_exact, w, a, kGravity, dt);
      CHECK(maxAbs(exact - expected) <= 1e-15 * maxAbs(expected));

      const Group X_first =
          inekf::propagateMean(X, w, a, kGravity, dt, Discretisation::kFirstOrder);
      const MatrixXd first =
          inekf::transition(X, X_first, w, a, kGravity, dt, Discretisation::kFirstOrder).matrix();
      CHECK(maxAbs(first - referencePhi(X, dt)) <= 1e-15 * maxAbs(first));
      // The reference's mean: R Exp(w dt), v + (R a + g) dt, p + v dt + (R a + g) dt^2 / 2.
      const Vector3d acc = X.R() * a + kGravity;
      CHECK((X_first.R() - X.R() * lie::SO3d::Exp(Vector3d(w * dt)).matrix()).norm() < 1e-14);
      CHECK((X_first.col(0) - (X.col(0) + acc * dt)).norm() < 1e-13);
      CHECK((X_first.col(1) - (X.col(1) + X.col(0) * dt + 0.5 * acc * dt * dt)).norm() < 1e-13);
      for (int i = 2; i < 2 + feet; ++i) CHECK(X_first.col(i) == X.col(i));
      // Both agree to first order in dt, and differ at second order (the test can tell them).
      CHECK(maxAbs(first - exact) < 50 * dt * dt * (1 + maxAbs(expected)));
      CHECK(maxAbs(first - exact) > 1e-3 * dt * dt);
    }
  }
}

// One step (propagation, stacked correction of the held feet, a new foot) against the dense
// formulas written out with full matrices: Phi, Adj, H, the Joseph update, the augmentation.
TEST_CASE("InEKF: one step equals the dense textbook formulas", "[57.5][inekf]") {
  for (const Discretisation mode : {Discretisation::kExact, Discretisation::kFirstOrder}) {
    CAPTURE(static_cast<int>(mode));
    std::mt19937 gen(7);
    InvariantEkfParams params;
    params.discretisation = mode;
    params.feet_correct_yaw = true;     // the textbook's gain (the heading rule: test_heading)
    params.foot_stance_density = 0.02;  // large enough to matter
    InvariantEkf filter(params);
    EstimateSample x0;
    x0.q = Eigen::Quaterniond(lie::SO3d::Random(gen).matrix());
    x0.v = normal3(gen, 1.0);
    x0.p = normal3(gen, 1.0);
    filter.reset(x0);
    const model::ImuReading u0{normal3(gen, 1.0), normal3(gen, 5.0)};
    const model::ImuReading u1{normal3(gen, 1.0), normal3(gen, 5.0)};
    const ContactMeasurement c0 = foothold(0, normal3(gen, 0.3), 0.01);
    const ContactMeasurement c2 = foothold(2, normal3(gen, 0.3), 0.02);
    filter.step(input(0.0, 0.0, u0, {c0, c2}));  // feet 0 and 2 become columns 2 and 3
    REQUIRE(filter.numFeet() == 2);
    REQUIRE(filter.columnOf(0) == 2);
    REQUIRE(filter.columnOf(2) == 3);
    // The new feet: d = p + R y, and their rows of P copy those of rho_p.
    CHECK((filter.X().col(2) - (x0.p + filter.X().R() * c0.p_body)).norm() < 1e-15);
    const Group X0 = filter.X();
    const MatrixXd P0 = filter.P();
    CHECK(maxAbs(P0.block(9, 0, 3, 9) - P0.block(6, 0, 3, 9)) == 0.0);

    const double dt = 0.004;
    const ContactMeasurement c0b = foothold(0, normal3(gen, 0.3), 0.01);
    const ContactMeasurement c2b = foothold(2, normal3(gen, 0.3), 0.03);
    const ContactMeasurement c3 = foothold(3, normal3(gen, 0.3), 0.01);
    filter.step(input(dt, dt, u1, {c2b, c3, c0b}));  // order of the contacts is irrelevant

    // Propagation with u0 (the held sample), biases zero.
    const int nav = 15, dim = nav + 6;
    const Group X_pred = inekf::propagateMean(X0, u0.w_m, u0.a_m, kGravity, dt, mode);
    MatrixXd Phi, Qd = MatrixXd::Zero(dim, dim);
    const model::ImuNoise& n = params.imu;
    const double sd2 = params.foot_stance_density * params.foot_stance_density;
    if (mode == Discretisation::kExact) {
      Phi = lie::imu::phiWithBias(X_pred, u0.w_m, u0.a_m, kGravity, dt);
      MatrixXd Qc = MatrixXd::Zero(6, 6);
      Qc.diagonal() << Vector3d::Constant(n.gyro_noise_density * n.gyro_noise_density),
          Vector3d::Constant(n.accel_noise_density * n.accel_noise_density);
      const MatrixXd B = Phi.topRightCorner(nav, 6);
      Qd.topLeftCorner(nav, nav) = B * Qc * B.transpose() / dt;
      Qd.block(9, 9, 6, 6).diagonal().array() += sd2 * dt;
      Qd.block(15, 15, 3, 3).diagonal().array() +=
          n.gyro_bias_random_walk * n.gyro_bias_random_walk * dt;
      Qd.block(18, 18, 3, 3).diagonal().array() +=
          n.accel_bias_random_walk * n.accel_bias_random_walk * dt;
    } else {
      Phi = referencePhi(X0, dt);
      MatrixXd G = MatrixXd::Identity(dim, dim);
      G.topLeftCorner(nav, nav) = X0.Adj();
      VectorXd q = VectorXd::Zero(dim);
      q << Vector3d::Constant(n.gyro_noise_density * n.gyro_noise_density),
          Vector3d::Constant(n.accel_noise_density * n.accel_noise_density), Vector3d::Zero(),
          Vector3d::Constant(sd2), Vector3d::Constant(sd2),
          Vector3d::Constant(n.gyro_bias_random_walk * n.gyro_bias_random_walk),
          Vector3d::Constant(n.accel_bias_random_walk * n.accel_bias_random_walk);
      Qd = Phi * G * q.asDiagonal() * G.transpose() * Phi.transpose() * dt;
    }
    const MatrixXd P_pred = Phi * P0 * Phi.transpose() + Qd;

    // Stacked correction of feet 0 (column 2) and 2 (column 3).
    const Matrix3d R = X_pred.R();
    MatrixXd H = MatrixXd::Zero(6, dim), N = MatrixXd::Zero(6, 6);
    VectorXd z(6);
    int row = 0;
    for (const auto& [c, col] : {std::pair<ContactMeasurement, int>{c0b, 2}, {c2b, 3}}) {
      H.block<3, 3>(row, 6) = -Matrix3d::Identity();
      H.block<3, 3>(row, 3 + 3 * col) = Matrix3d::Identity();
      N.block<3, 3>(row, row) = R * c.cov * R.transpose();
      z.segment<3>(row) = R * c.p_body + X_pred.col(1) - X_pred.col(col);
      row += 3;
    }
    const MatrixXd S = H * P_pred * H.transpose() + N;
    const MatrixXd K = P_pred * H.transpose() * S.inverse();
    const VectorXd delta = K * z;
    const Group X_upd = Group::Exp(delta.head(nav)) * X_pred;
    const MatrixXd IKH = MatrixXd::Identity(dim, dim) - K * H;
    const MatrixXd P_upd = IKH * P_pred * IKH.transpose() + K * N * K.transpose();

    // Augmentation with foot 3 (column 4): F copies rho_p, plus R Cov R^T.
    MatrixXd F = MatrixXd::Zero(dim + 3, dim);
    F.topLeftCorner(nav, nav).setIdentity();
    F.block<3, 3>(nav, 6).setIdentity();
    F.bottomRightCorner(6, 6).setIdentity();
    MatrixXd Gn = MatrixXd::Zero(dim + 3, 3);
    Gn.block<3, 3>(nav, 0) = X_upd.R();
    const MatrixXd P_expected = F * P_upd * F.transpose() + Gn * c3.cov * Gn.transpose();

    REQUIRE(filter.numFeet() == 3);
    CHECK(filter.columnOf(3) == 4);
    CHECK(filter.columnOf(1) == -1);
    CHECK((filter.X().R() - X_upd.R()).norm() < 1e-12);
    for (int i = 0; i < 4; ++i) CHECK((filter.X().col(i) - X_upd.col(i)).norm() < 1e-12);
    CHECK((filter.X().col(4) - (X_upd.col(1) + X_upd.R() * c3.p_body)).norm() < 1e-12);
    CHECK((filter.b_g() - delta.segment<3>(nav)).norm() < 1e-12);
    CHECK((filter.b_a() - delta.segment<3>(nav + 3)).norm() < 1e-12);
    REQUIRE(filter.P().rows() == dim + 3);
    CHECK(maxAbs(filter.P() - P_expected) <= 1e-10 * maxAbs(P_expected));
    CHECK(maxAbs(delta) > 1e-4);  // the correction did something
  }
}

TEST_CASE("InEKF: without contacts it is dead reckoning with lie::imu::propagate",
          "[57.5][inekf]") {
  std::mt19937 gen(3);
  InvariantEkf filter;
  EstimateSample x0;
  x0.v = Vector3d(0.5, 0.0, 0.1);
  filter.reset(x0);
  Group X(2);
  X.col(0) = x0.v;
  model::ImuReading previous;
  double t = 0.0;
  for (int k = 0; k < 500; ++k) {
    const double dt = k == 0 ? 0.0 : 0.001 + 0.001 * (k % 3);
    t += dt;
    const model::ImuReading u{normal3(gen, 1.0), normal3(gen, 5.0)};
    filter.step(input(t, dt, u, {}));
    if (k > 0) X = lie::imu::propagate(X, previous.w_m, previous.a_m, kGravity, dt);
    previous = u;
    REQUIRE(filter.X().isApprox(X, 1e-12));
    REQUIRE(filter.b_g().norm() == 0.0);  // nothing observes the biases
    REQUIRE(filter.P().rows() == 15);
  }
  CHECK(filter.estimate().t == Approx(t));
  CHECK(X.col(1).norm() > 0.1);  // it moved
}

TEST_CASE("InEKF: contacts added and removed keep P symmetric positive definite", "[57.5][inekf]") {
  std::mt19937 gen(5);
  InvariantEkf filter;
  filter.reset(EstimateSample{});
  std::uniform_int_distribution<int> coin(0, 1);
  std::array<Vector3d, inekf::kMaxFeet> foot_body;
  for (Vector3d& f : foot_body) f = normal3(gen, 0.3);
  int changes = 0;
  int previous = 0;
  for (int k = 0; k < 400; ++k) {
    std::vector<ContactMeasurement> stance;
    for (int foot = 0; foot < inekf::kMaxFeet; ++foot) {
      if (coin(gen)) stance.push_back(foothold(foot, foot_body[foot] + normal3(gen, 0.005), 0.005));
    }
    const model::ImuReading u{normal3(gen, 0.2), Vector3d(0, 0, 9.81) + normal3(gen, 0.2)};
    filter.step(input(k * 1e-3, k == 0 ? 0.0 : 1e-3, u, stance));
    const MatrixXd P = filter.P();
    REQUIRE(filter.numFeet() == static_cast<int>(stance.size()));
    REQUIRE(P.rows() == 15 + 3 * filter.numFeet());
    REQUIRE(P.allFinite());
    REQUIRE(maxAbs(P - P.transpose()) <= 1e-15 * maxAbs(P));
    REQUIRE(minEigenvalue(P) > 0.0);
    std::vector<bool> used(2 + inekf::kMaxFeet, false);
    for (const ContactMeasurement& c : stance) {
      const int col = filter.columnOf(c.foot);
      REQUIRE(col >= 2);
      REQUIRE(!used[col]);
      used[col] = true;
    }
    changes += filter.numFeet() != previous;
    previous = filter.numFeet();
  }
  CHECK(changes > 100);

  // Removal is marginalisation and a touchdown only augments: with dt = 0 (no propagation) and no
  // held foot in stance (no correction), P changes by exactly those operations.
  filter.step(input(1.0, 0.0, {}, {}));
  REQUIRE(filter.numFeet() == 0);
  const MatrixXd empty = filter.P();
  filter.step(input(1.0, 0.0, {}, {foothold(2, foot_body[2], 0.005)}));
  const MatrixXd held = filter.P();
  REQUIRE(held.rows() == 18);
  CHECK(held.topLeftCorner(9, 9) == empty.topLeftCorner(9, 9));
  CHECK(held.block(9, 0, 3, 9) == empty.block(6, 0, 3, 9));  // rho_d = rho_p + R n
  CHECK(held.bottomRightCorner(6, 6) == empty.bottomRightCorner(6, 6));
  filter.step(input(1.0, 0.0, {}, {}));
  MatrixXd marginal(15, 15);
  marginal << held.topLeftCorner(9, 9), held.topRightCorner(9, 6), held.bottomLeftCorner(6, 9),
      held.bottomRightCorner(6, 6);
  CHECK(filter.P() == marginal);
}

TEST_CASE("InEKF: a correction reduces the covariance along H and nowhere grows it",
          "[57.5][inekf]") {
  // The optimal gain's property, of the plain filter. The heading rule's gain (I - E) K (the
  // default) is not optimal: its Joseph update may grow the covariance along a direction that
  // mixes the heading with the rest (here by 5e-9 against 6e-4 along H).
  InvariantEkfParams plain;
  plain.feet_correct_yaw = true;
  InvariantEkf filter(plain);
  filter.reset(EstimateSample{});
  const ContactMeasurement c1 = foothold(1, Vector3d(0.2, -0.1, -0.3), 0.01);
  const ContactMeasurement c3 = foothold(3, Vector3d(-0.2, 0.1, -0.3), 0.01);
  const model::ImuReading still{Vector3d::Zero(), Vector3d(0, 0, 9.81)};
  filter.step(input(0.0, 0.0, still, {c1, c3}));
  // Hold both feet for 0.2 s with their measurements made nearly useless (huge covariance), so
  // that the uncertainty along H grows; then one correction with the true noise (dt = 0: no
  // propagation in between).
  ContactMeasurement vague1 = c1, vague3 = c3;
  vague1.cov *= 1e10;
  vague3.cov *= 1e10;
  for (int k = 1; k <= 200; ++k) filter.step(input(k * 1e-3, 1e-3, still, {vague1, vague3}));
  const MatrixXd before = filter.P();
  const int col = filter.columnOf(1);
  MatrixXd H = MatrixXd::Zero(3, before.rows());
  H.block<3, 3>(0, 6) = -Matrix3d::Identity();
  H.block<3, 3>(0, 3 + 3 * col) = Matrix3d::Identity();
  filter.step(input(0.2, 0.0, still, {c1, c3}));
  const MatrixXd after = filter.P();
  const Matrix3d along_before = H * before * H.transpose();
  const Matrix3d along_after = H * after * H.transpose();
  CAPTURE(along_before.trace(), along_after.trace());
  // Each foot's relative position is known to ~ its measurement noise after the update.
  CHECK(along_after.trace() < 0.5 * along_before.trace());
  CHECK(along_after.trace() < 4 * c1.cov.trace());
  CHECK(minEigenvalue(before - after) > -1e-15 * maxAbs(before));  // P never grows
  CHECK(minEigenvalue(after) > 0.0);
}

TEST_CASE("InEKF: covariance() maps xi to the kit's convention to first order", "[57.5][inekf]") {
  std::mt19937 gen(13);
  for (int trial = 0; trial < 20; ++trial) {
    const Group X_hat = randomGroup(gen, 2);
    EstimateSample estimate;
    estimate.q = Eigen::Quaterniond(X_hat.R());
    estimate.v = X_hat.col(0);
    estimate.p = X_hat.col(1);
    Eigen::Matrix<double, 9, 9> T = Eigen::Matrix<double, 9, 9>::Identity();  // e = -T xi
    T.block<3, 3>(3, 0) = -lie::hat3(Vector3d(X_hat.col(0)));
    T.block<3, 3>(6, 0) = -lie::hat3(Vector3d(X_hat.col(1)));
    for (const double scale : {1e-4, 1e-3}) {
      Eigen::Matrix<double, 9, 1> xi;
      for (int i = 0; i < 9; ++i) xi(i) = std::normal_distribution<double>(0.0, scale)(gen);
      const Group X = Group::Exp(Group::Tangent(-xi)) * X_hat;  // eta = X_hat X^-1 = Exp(xi)
      REQUIRE(((X_hat * X.inverse()).Log() - xi).norm() < 1e-12);
      EstimateSample truth;
      truth.q = Eigen::Quaterniond(X.R());
      truth.v = X.col(0);
      truth.p = X.col(1);
      const Eigen::Matrix<double, 9, 1> e = eval::baseError(truth, estimate);
      // First order: the remainder shrinks like |xi|^2 (times the size of v and p).
      CHECK((e + T * xi).norm() < 20 * scale * scale * (1 + X_hat.columns().norm()));
    }
  }
  // And the filter reports T P T^T, which at reset is the prior it was given.
  InvariantEkfParams params;
  InvariantEkf filter(params);
  EstimateSample x0;
  x0.q = Eigen::Quaterniond(lie::SO3d::Random(gen).matrix());
  x0.v = Vector3d(1.0, -0.5, 0.2);
  x0.p = Vector3d(3.0, 2.0, 0.4);
  filter.reset(x0);
  Eigen::Matrix<double, 9, 1> sigma;
  sigma << Vector3d::Constant(params.sigma_attitude), Vector3d::Constant(params.sigma_velocity),
      Vector3d::Constant(params.sigma_position);
  const BaseCovariance cov = *filter.covariance();
  CHECK(cov.has_attitude);
  CHECK((cov.P - Eigen::Matrix<double, 9, 9>(sigma.array().square().matrix().asDiagonal())).norm() <
        1e-15);
  CHECK(filter.P().topLeftCorner<9, 9>().isDiagonal() == false);  // xi's prior is correlated
}

TEST_CASE("InEKF: a noiseless trot is tracked, with either discretisation", "[57.5][inekf]") {
  for (const Discretisation mode : {Discretisation::kExact, Discretisation::kFirstOrder}) {
    INFO("mode " << static_cast<int>(mode));
    InvariantEkfParams params;
    params.discretisation = mode;
    InvariantEkf filter(params);
    legkit::test::checkNoiselessTrotTracked(
        filter, [](const InvariantEkf& f, int i) { return f.columnOf(i) >= 0; });
  }
}

TEST_CASE("InEKF: bad input throws and leaves the state untouched", "[57.5][inekf]") {
  InvariantEkf filter;
  const StepInput good = stepToTwoFeet(filter);
  const Group X_before = filter.X();
  const MatrixXd P_before = filter.P();
  const Vector3d b_g = filter.b_g(), b_a = filter.b_a();
  const double t_before = filter.estimate().t;
  std::array<int, inekf::kMaxFeet> columns{};
  for (int i = 0; i < inekf::kMaxFeet; ++i) columns[i] = filter.columnOf(i);
  checkStepFaultsRefused(filter, good, [&] {
    CHECK(filter.X().R() == X_before.R());
    CHECK(filter.X().columns() == X_before.columns());
    CHECK(filter.P() == P_before);
    CHECK(filter.b_g() == b_g);
    CHECK(filter.b_a() == b_a);
    CHECK(filter.estimate().t == t_before);
    for (int i = 0; i < inekf::kMaxFeet; ++i) CHECK(filter.columnOf(i) == columns[i]);
  });
  checkFamilyParamsRefused<InvariantEkf, InvariantEkfParams>();
}

TEST_CASE("InEKF: Monte Carlo NEES on the trot, the simulator's noise model",
          "[57.5][inekf][nees][study]") {
  for (const Discretisation mode : {Discretisation::kExact, Discretisation::kFirstOrder}) {
    InvariantEkfParams params;
    params.discretisation = mode;
    params.foot_stance_density = 1e-4;
    const NeesResult r = monteCarloNees<InvariantEkf>(20, params, 1.0, simulatorFrontend(), kWorld);
    WARN("InEKF (" << (mode == Discretisation::kExact ? "exact" : "first order")
                   << "): " << describe(r));
    CHECK(r.mean > r.bounds.lower);
    CHECK(r.mean < r.bounds.upper);
    CHECK(r.fraction > 0.8);
  }
}

TEST_CASE("InEKF: Monte Carlo NEES on the trot, the kit's defaults", "[57.5][inekf][nees][study]") {
  const NeesResult r =
      monteCarloNees<InvariantEkf>(20, InvariantEkfParams{}, 1.0, FrontendNoise{}, kWorld);
  WARN("InEKF (defaults): " << describe(r));
  CHECK(r.mean > 0.8 * r.bounds.lower);
  CHECK(r.mean < r.bounds.upper);
}

// The ESKF's large-error test (eskf_test.cpp) with the same seeds, prior and draw x10 (0.1 rad,
// 0.5 m/s, 0.1 m): the ESKF reports 287 on these 10 runs, over-confident. The InEKF's navigation
// error propagates exactly whatever its size, and it stays consistent. Measured (these seeds,
// 10 runs): mean 8.36 inside [6.56, 11.81], 99.6 % of rows inside.
TEST_CASE("InEKF: Monte Carlo NEES, large initial error: still consistent",
          "[57.5][inekf][nees][study]") {
  InvariantEkfParams params;
  params.foot_stance_density = 1e-4;
  const NeesResult r = monteCarloNees<InvariantEkf>(10, params, 10.0, simulatorFrontend(), kWorld);
  WARN("InEKF, initial error x10: " << describe(r));
  CHECK(r.mean > r.bounds.lower);
  CHECK(r.mean < r.bounds.upper);
}

namespace {

// The reference's Cassie example with `params` (InvariantEkfParams::hartleyExample and
// variations), as eval::runHartleyLog runs it; `after` sees the filter after every record.
InvariantEkf runCassie(const io::HartleyLog& log, const InvariantEkfParams& params,
                       const std::function<void(const InvariantEkf&)>& after = {}) {
  InvariantEkf filter(params);
  eval::runHartleyLog(filter, log, [&] {
    if (after) after(filter);
  });
  return filter;
}

// The log shipped in data/hartley-cassie/, unpacked into the build tree by CMake
// (LEGKIT_CASSIE_LOG_FILE), unless LEGKIT_CASSIE_LOG points elsewhere.
std::string cassiePath() {
  if (const char* env = std::getenv("LEGKIT_CASSIE_LOG")) return env;
  return LEGKIT_CASSIE_LOG_FILE;
}

io::HartleyLog readCassie() {
  const std::string path = cassiePath();
  INFO("the Cassie log (data/hartley-cassie/, or LEGKIT_CASSIE_LOG): " << path);
  REQUIRE(std::ifstream(path).good());
  io::HartleyLog log = io::readHartleyLog(path);
  REQUIRE(log.samples.size() == 19992);
  return log;
}

const char* kFoot =
    " 0 0.0 0.7071 0.7071 0.0 -0.03 -0.13 0.92"
    " 0 0 0 0 0 0  0 0 0 0 0 0  0 0 0 0 0 0  0 0 0 1e-4 0 0  0 0 0 0 1e-4 0  0 0 0 0 0 1e-5";

io::HartleyLog parse(const std::string& text) {
  std::istringstream in(text);
  return io::parseHartleyLog(in, "test.txt");
}

}  // namespace

TEST_CASE("Hartley log reader: records, stance feet and errors with file:line", "[57.5][io]") {
  const std::string good = std::string("IMU 0.5 0.1 0.2 0.3 1 2 3\nCONTACT 0.5 0 1 1 0\n") +
                           "KINEMATIC 0.5" + kFoot + kFoot + "\n";
  std::string two = good;
  two.replace(two.find(kFoot) + std::string(kFoot).size() + 1, 1, "1");  // second foot id 1
  const io::HartleyLog log =
      parse(two + "IMU 0.6 0 0 0 0 0 9.8\nCONTACT 0.6 0 0 1 1\nKINEMATIC 0.6" + kFoot + "\n");
  REQUIRE(log.samples.size() == 2);
  const io::HartleySample& s = log.samples[0];
  CHECK(s.t == 0.5);
  CHECK(s.imu.w_m == Vector3d(0.1, 0.2, 0.3));
  CHECK(s.imu.a_m == Vector3d(1, 2, 3));
  REQUIRE(s.num_feet == 2);
  CHECK(s.feet[0].p_body == Vector3d(-0.03, -0.13, 0.92));
  CHECK(s.feet[0].cov == Vector3d(1e-4, 1e-4, 1e-5).asDiagonal().toDenseMatrix());
  std::array<ContactMeasurement, io::kHartleyMaxFeet> stance;
  REQUIRE(io::stanceFeet(s, stance) == 1);
  CHECK(stance[0].foot == 0);
  // Foot 0 is up; foot 1 is down but has no kinematics: nothing to measure (as in the reference).
  CHECK(io::stanceFeet(log.samples[1], stance) == 0);
  CHECK(log.samples[1].line == 4);

  const auto rejects = [](const std::string& text, const std::string& where,
                          const std::string& what) {
    INFO(text);
    CHECK_THROWS_WITH(parse(text), Catch::Contains(where) && Catch::Contains(what));
  };
  rejects("IMU 0.5 0.1 0.2 x 1 2 3\n", "test.txt:1: column 'wz'", "expected a number");
  rejects("IMU 0.5 0.1 0.2 nan 1 2 3\n", "test.txt:1: column 'wz'", "not finite");
  rejects("IMU 0.5 0.1 0.2 1 2 3\n", "test.txt:1", "IMU record needs 8 fields");
  rejects(two + "IMU 0.5 0 0 0 0 0 0\n", "test.txt:4: column 't'", "not after");
  rejects(good, "test.txt:3: column 'id1'", "foot listed twice");
  rejects("CONTACT 0.5 0 1\n", "test.txt:1: column 't'", "without an IMU record");
  rejects("IMU 0.5 0 0 0 0 0 0\nCONTACT 0.5 0 2\n", "test.txt:2: column 'c0'", "0 or 1");
  rejects("IMU 0.5 0 0 0 0 0 0\nCONTACT 0.5 7 1\n", "test.txt:2: column 'id0'", "foot id");
  rejects("IMU 0.5 0 0 0 0 0 0\nCONTACT 0.5 0 1\nKINEMATIC 0.5 0 1 2\n", "test.txt:3",
          "44 fields per foot");
  rejects("IMU 0.5 0 0 0 0 0 0\nCONTACT 0.5 0 1\n", "test.txt:2", "no KINEMATIC record");
  rejects("IMU 0.5 0 0 0 0 0 0\nCONTACT 0.5 1 1\nKINEMATIC 0.5" + std::string(kFoot) + "\n",
          "test.txt:3", "foot 0 of the sample of line 1 has no contact indicator");
  rejects("GPS 0.5 1 2 3\n", "test.txt:1", "unknown record 'GPS'");
  rejects("", "test.txt", "no IMU record");
  CHECK_THROWS_WITH(io::readHartleyLog("/nonexistent/log.txt"), Catch::Contains("cannot open"));
}

// The whole reference log (10 s of Cassie walking, 19,992 samples, one or two feet down) with the
// reference's settings. There is no ground truth: the checks are that nothing diverges, the
// covariance stays bounded and positive definite, and the final state is physically sane.
TEST_CASE("InEKF on the reference's Cassie log", "[57.5][inekf][cassie]") {
  const io::HartleyLog log = readCassie();
  const InvariantEkf filter = runCassie(log, InvariantEkfParams::hartleyExample());
  const EstimateSample x = filter.estimate();
  const MatrixXd& P = filter.P();
  std::ostringstream os;
  os.precision(6);
  os << "final state at t = " << x.t << ":\nR =\n"
     << filter.X().R() << "\nv = " << x.v.transpose() << "\np = " << x.p.transpose()
     << "\nb_g = " << filter.b_g().transpose() << "\nb_a = " << filter.b_a().transpose()
     << "\nfeet held: " << filter.numFeet()
     << ", sigma (theta, v, p) = " << filter.covariance()->P.diagonal().cwiseSqrt().transpose();
  WARN(os.str());
  CHECK(x.t == 10.0);
  REQUIRE(P.allFinite());
  REQUIRE(filter.X().matrix().allFinite());
  CHECK(minEigenvalue(P) > 0.0);
  CHECK(P.diagonal().maxCoeff() < 10.0);  // bounded (P0 = I)
  CHECK((filter.X().R().transpose() * filter.X().R() - Matrix3d::Identity()).norm() < 1e-12);
  // Sane for a walking biped: upright IMU frame (R0 = diag(1, -1, -1): z down), slow, near the
  // start, small biases.
  CHECK((filter.X().R() * Vector3d::UnitZ()).z() < -0.9);
  CHECK(x.v.norm() < 2.0);
  CHECK(x.p.norm() < 10.0);
  CHECK(std::abs(x.p.z()) < 0.5);
  CHECK(filter.b_g().norm() < 0.1);
  CHECK(filter.b_a().norm() < 1.0);
}

namespace {
// The reference implementation's states on this log, printed with 17 digits by its own code:
// RossHartley/invariant-ekf at commit 981e64f765f27b7955ef4f121673788ca8598ca0 (src/InEKF.cpp,
// src/RobotState.cpp, include/*.h; src/LieGroup.cpp as of 43aab8a, the same Exp_SO3/Exp_SEK3),
// the loop and settings of its src/examples/kinematics.cpp, built with
// g++ 12 -O2 -std=c++17 against Debian's Eigen 3.4 and run on data/hartley-cassie/ (SHA-256
// 224e03c8...), printing the state after the KINEMATIC record of t = 0.5, 2.5, 5, 7.5 and 10 s.
// External reference figures, not this kit's results.
struct ReferenceState {
  double t;
  int feet;     // contact columns held
  double R[9];  // row-major
  double v[3], p[3], b_g[3], b_a[3];
  double sigma[15];  // square roots of P's diagonal: phi, rho_v, rho_p, b_g, b_a
};
const ReferenceState kReference[] = {
    {0.5,
     1,
     {0.99911020792539518, -0.010541100052372852, -0.040837208878220392, -0.0036163916084025935,
      -0.9861087302717414, 0.16606171682116008, -0.042020401366623494, -0.16576627308214018,
      -0.98526941928462075},
     {0.32398185297951843, -0.18085293941669722, 0.75070764910923538},
     {0.057458048288150175, 0.002388934795369984, -0.15737018274110764},
     {-0.032780635011202257, -0.051056097137439825, 0.026765193876913035},
     {-0.037878216249579252, -0.10357079800740605, -0.093437295067977655},
     {0.10019739553380778, 0.11849590015515062, 1.0019685336077184, 0.282407649654768,
      0.10484993466993749, 0.0476758319044479, 1.0159377209350613, 1.0019269121285781,
      1.0000588146454226, 0.12984854097583107, 0.3774833898051782, 0.13072394330029885,
      0.99393571506935985, 0.94182603368653106, 0.26924778785463249}},
    {2.5,
     2,
     {0.99421370447297219, 0.10739164607838708, 0.0024787478101219798, 0.1074201493455494,
      -0.99397944644981884, -0.021581741122892226, 0.00014612567176949622, 0.021723130250720007,
      -0.99976401428508621},
     {0.27258586543317442, -0.092253898901304879, 0.1583372549571728},
     {0.64380382718840756, 0.00851849786884744, -0.15202285547044139},
     {-0.0022673897049146161, 0.00095929474562808474, 0.013867644283082346},
     {-0.12275996158064131, -0.03449870717453158, -0.0027007112666905956},
     {0.070323104307505185, 0.097838276562654702, 1.0114209194989845, 0.046439331862163452,
      0.04484625729525895, 0.028657698776347381, 1.0007397702929495, 1.0015662094514381,
      1.0001613594751153, 0.015270264737669745, 0.014973570060415334, 0.061232113493470554,
      0.95257998259983312, 0.65820765795126002, 0.06950750695641543}},
    {5.0,
     1,
     {0.99576591453089769, 0.089761673361133748, -0.019826382772364062, 0.086688294693758092,
      -0.98869464883281244, -0.12234390435348724, -0.030584032133052205, 0.12010717449335093,
      -0.9922897175793649},
     {0.24337342300824916, 0.035535571134500919, -0.051984796738550658},
     {1.2256907025124952, 0.017396034952191625, -0.14564365243720484},
     {0.0004467320787620928, 0.00056238052123508821, 0.0036678939786176515},
     {-0.1056277281783219, -0.03021049674205168, 0.00015356079874119611},
     {0.055787788679307816, 0.090318304102744204, 1.0252036382213157, 0.044238355079480374,
      0.043122563994248207, 0.032551685101404569, 1.0005380524664342, 1.0092726359851998,
      1.0003238017394838, 0.0065915161284961525, 0.006447109825508961, 0.045615061050666449,
      0.88057393590214073, 0.5237787032638993, 0.048288189386483257}},
    {7.5,
     2,
     {0.99694605902069422, 0.07792635515859396, 0.0051028006808801468, 0.078092991278745499,
      -0.99464462755223249, -0.067701917215193613, -0.00020029036312197075, 0.067893652524905368,
      -0.99769254373810856},
     {0.22511839821313273, 0.11791739612139621, 0.01012892261362189},
     {1.8165730752353908, 0.01962608976591413, -0.1428972658939156},
     {0.00024399384234085415, 0.00039849358527249901, 0.00052818497822125813},
     {-0.13038471809164803, -0.030406998046088859, 0.002013865652930746},
     {0.047959798933343879, 0.087154515578446112, 1.0389179977876375, 0.042015778825874796,
      0.040714276175617514, 0.029908150788699735, 1.0005783179404037, 1.031357353815233,
      1.000522780306238, 0.0045751201809578002, 0.004530431410669093, 0.037909983222088155,
      0.84938926325622655, 0.44997402859700336, 0.039242099767075433}},
    {10.0,
     1,
     {0.99619828841986835, 0.082731153961061329, -0.027286009484540283, 0.084970844068390769,
      -0.99184806844842177, 0.094959806094181171, -0.019207441464815327, -0.096917311556864741,
      -0.99510708414371296},
     {0.14887802088007968, 0.012131360335162412, 0.035031628245145531},
     {2.3988249246417945, 0.015561227850400341, -0.11133116062094089},
     {-0.00025836440128098275, 0.00028684704151662696, -0.00030471865336014815},
     {-0.17874183222010018, -0.018196400691220957, 0.0023015737080947425},
     {0.043164770225674151, 0.085485449889889445, 1.0516508026444751, 0.041948124076293468,
      0.040737693166787048, 0.031279521048942972, 1.000661229791878, 1.0726562806316429,
      1.0007677956971468, 0.0036973922955813869, 0.0036843827000283386, 0.032856145877874228,
      0.83251738806772313, 0.403621194798711, 0.033890377530327032}},
};

// The largest differences between the filter and the reference's states at its five times, over
// a whole run: of the state (R, v, p and the biases), and of the standard deviations (P's
// diagonal, for the same error xi in both).
struct Difference {
  double state = 0.0;
  double sigma = 0.0;
};
Difference differenceToReference(const io::HartleyLog& log, const InvariantEkfParams& params) {
  const auto v3 = [](const double* x) { return Vector3d(x[0], x[1], x[2]); };
  Difference worst;
  int compared = 0;
  runCassie(log, params, [&](const InvariantEkf& f) {
    for (const ReferenceState& r : kReference) {
      if (f.estimate().t != r.t) continue;
      CHECK(f.numFeet() == r.feet);
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(r.R);
      worst.state = std::max({worst.state, (f.X().R() - R).cwiseAbs().maxCoeff(),
                              (f.X().col(0) - v3(r.v)).cwiseAbs().maxCoeff(),
                              (f.X().col(1) - v3(r.p)).cwiseAbs().maxCoeff(),
                              (f.b_g() - v3(r.b_g)).cwiseAbs().maxCoeff(),
                              (f.b_a() - v3(r.b_a)).cwiseAbs().maxCoeff()});
      Eigen::Matrix<double, 15, 1> variance;
      variance << f.P().diagonal().head<9>(), f.P().diagonal().tail<6>();
      const Eigen::Map<const Eigen::Matrix<double, 15, 1>> sigma(r.sigma);
      worst.sigma = std::max(worst.sigma, (variance.cwiseSqrt() - sigma).cwiseAbs().maxCoeff());
      ++compared;
    }
  });
  CHECK(compared == 5);
  return worst;
}

}  // namespace

// With the reference's touchdown attitude the kit is the reference, to rounding: the remaining
// differences come from the order of operations (sequential 3 x 3 updates instead of one stacked
// inverse, P - K H P instead of the Joseph form, the attitude kept as a unit quaternion).
TEST_CASE("InEKF on the Cassie log: TouchdownAttitude::kPredicted gives the reference's states",
          "[57.5][inekf][cassie]") {
  const io::HartleyLog log = readCassie();
  InvariantEkfParams params = InvariantEkfParams::hartleyExample();
  params.touchdown_attitude = inekf::TouchdownAttitude::kPredicted;
  const Difference as_reference = differenceToReference(log, params);
  const Difference kit = differenceToReference(log, InvariantEkfParams::hartleyExample());
  WARN("largest difference to the reference's states: "
       << as_reference.state << " (sigmas " << as_reference.sigma << ") with kPredicted, "
       << kit.state << " (sigmas " << kit.sigma << ") with the kit's kCorrected");
  CHECK(as_reference.state < 1e-9);
  CHECK(as_reference.sigma < 1e-9);
  CHECK(kit.state > 1e-4);  // measured 2.5e-4: one attitude correction times the leg, at touchdowns
  CHECK(kit.state < 1e-3);
}

// The checkpoints above see the two touchdown attitudes differ by 2.5e-4; over every record of the
// log the difference is larger, right after the first touchdowns, where the first attitude
// corrections are largest (chapter 57.5 quotes these figures).
TEST_CASE("InEKF on the Cassie log: kCorrected against kPredicted over the whole log",
          "[57.5][inekf][cassie]") {
  const io::HartleyLog log = readCassie();
  InvariantEkfParams params = InvariantEkfParams::hartleyExample();
  std::vector<Eigen::Matrix<double, 13, 1>> kit;  // t, v, p, b_g, b_a after each record
  kit.reserve(log.samples.size());
  const auto state = [](const InvariantEkf& f) {
    Eigen::Matrix<double, 13, 1> x;
    x << f.estimate().t, f.estimate().v, f.estimate().p, f.b_g(), f.b_a();
    return x;
  };
  runCassie(log, params, [&](const InvariantEkf& f) { kit.push_back(state(f)); });
  params.touchdown_attitude = inekf::TouchdownAttitude::kPredicted;
  std::size_t k = 0;
  const char* names[] = {"v", "p", "b_g", "b_a"};
  double largest[4] = {0, 0, 0, 0}, when[4] = {0, 0, 0, 0};
  runCassie(log, params, [&](const InvariantEkf& f) {
    const Eigen::Matrix<double, 13, 1> d = (state(f) - kit[k]).cwiseAbs();
    for (int b = 0; b < 4; ++b) {
      if (d.segment<3>(1 + 3 * b).maxCoeff() > largest[b]) {
        largest[b] = d.segment<3>(1 + 3 * b).maxCoeff();
        when[b] = kit[k](0);
      }
    }
    ++k;
  });
  std::ostringstream os;
  os << "kCorrected - kPredicted over the log, largest |difference| and when:";
  for (int b = 0; b < 4; ++b)
    os << "  " << names[b] << " " << largest[b] << " at " << when[b] << " s";
  WARN(os.str());
  const double worst = *std::max_element(largest, largest + 4);
  CHECK(worst > 2.5e-4);  // more than the checkpoints show (measured 1.6e-3, b_g)
  CHECK(worst < 5e-3);    // still a rounding-sized choice next to the state (|v| ~ 1 m/s)
}

TEST_CASE("InEKF: a hexapod standing holds six feet and stays at the truth", "[57.5][inekf]") {
  // Six feet around a body at rest 0.3 m above the ground, exact readings: the estimate must not
  // move, every foot is held, and P stays symmetric positive definite.
  InvariantEkf filter;
  filter.reset(
      EstimateSample{0.0, Eigen::Quaterniond::Identity(), Vector3d::Zero(), Vector3d(0, 0, 0.3)});
  std::vector<ContactMeasurement> feet;
  for (int i = 0; i < 6; ++i) {
    const double angle = i * M_PI / 3.0;
    feet.push_back(
        foothold(i, Vector3d(0.4 * std::cos(angle), 0.4 * std::sin(angle), -0.3), 0.005));
  }
  const model::ImuReading still{Vector3d::Zero(), Vector3d(0, 0, 9.81)};
  for (int k = 0; k <= 2000; ++k) filter.step(input(k * 1e-3, k == 0 ? 0.0 : 1e-3, still, feet));
  CHECK(filter.numFeet() == 6);
  for (int i = 0; i < 6; ++i) CHECK(filter.columnOf(i) >= 2);
  CHECK(filter.estimate().p.isApprox(Vector3d(0, 0, 0.3), 1e-9));
  CHECK(filter.estimate().v.norm() < 1e-9);
  CHECK(filter.P().rows() == 15 + 18);
  CHECK(minEigenvalue(filter.P()) > 0.0);
  CHECK(filter.health().total() == 0);
}
