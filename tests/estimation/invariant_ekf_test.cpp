// The right-invariant EKF (section 57.5): its Phi blocks against lie::imu::phiWithBias and the
// reference's I + A dt, one whole step against the dense textbook formulas (both
// discretisations), contacts added and removed, the update along H, the covariance mapping,
// dead reckoning against lie::imu::propagate, bad input, no allocation in step(), Monte Carlo
// NEES on the simulated trot, and the reference's Cassie log (reader and whole run).
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <atomic>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <new>
#include <random>
#include <sstream>

#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/consistency.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "io/hartley_log.hpp"
#include "io/log_error.hpp"
#include "lie/imu_dynamics.hpp"
#include "sim/simulator.hpp"

// Counts every heap allocation of this program, to show that InvariantEkf::step makes none.
namespace {
std::atomic<long> g_allocations{0};
}
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  return operator new(size);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

using namespace legkit;
using namespace legkit::invariant;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using inekf::Discretisation;
using inekf::Group;

namespace {

const Vector3d kGravity = model::gravity();

Vector3d normal3(std::mt19937& gen, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  return {n(gen), n(gen), n(gen)};
}

Group randomGroup(std::mt19937& gen, int columns) {
  Group::Columns C(3, columns);
  for (int i = 0; i < columns; ++i) C.col(i) = normal3(gen, 2.0);
  return Group(lie::SO3d::Random(gen), C);
}

ContactMeasurement contact(int foot, const Vector3d& p_body, double sigma) {
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

io::Log trotLog(double duration, unsigned seed, bool noiseless,
                const model::ImuBias& bias = model::ImuBias{}) {
  sim::SimOptions options;
  options.scenario = sim::scenarioByName("trot");
  options.duration = duration;
  options.seed = seed;
  options.initial_bias = bias;
  if (noiseless) options.noiseless();
  return sim::simulate(options).log;
}

std::vector<StepInput> inputsOf(const io::Log& log) {
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  std::vector<StepInput> inputs;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const double dt = k == 0 ? 0.0 : log.rows[k].t - log.rows[k - 1].t;
    inputs.push_back(frontend.input(log.rows[k], dt));
  }
  return inputs;
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
    params.foot_density = 0.02;  // large enough to matter
    InvariantEkf filter(params);
    EstimateSample x0;
    x0.q = Eigen::Quaterniond(lie::SO3d::Random(gen).matrix());
    x0.v = normal3(gen, 1.0);
    x0.p = normal3(gen, 1.0);
    filter.reset(x0);
    const model::ImuReading u0{normal3(gen, 1.0), normal3(gen, 5.0)};
    const model::ImuReading u1{normal3(gen, 1.0), normal3(gen, 5.0)};
    const ContactMeasurement c0 = contact(0, normal3(gen, 0.3), 0.01);
    const ContactMeasurement c2 = contact(2, normal3(gen, 0.3), 0.02);
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
    const ContactMeasurement c0b = contact(0, normal3(gen, 0.3), 0.01);
    const ContactMeasurement c2b = contact(2, normal3(gen, 0.3), 0.03);
    const ContactMeasurement c3 = contact(3, normal3(gen, 0.3), 0.01);
    filter.step(input(dt, dt, u1, {c2b, c3, c0b}));  // order of the contacts is irrelevant

    // Propagation with u0 (the held sample), biases zero.
    const int nav = 15, dim = nav + 6;
    const Group X_pred = inekf::propagateMean(X0, u0.w_m, u0.a_m, kGravity, dt, mode);
    MatrixXd Phi, Qd = MatrixXd::Zero(dim, dim);
    const model::ImuNoise& n = params.imu;
    const double sd2 = params.foot_density * params.foot_density;
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
      if (coin(gen)) stance.push_back(contact(foot, foot_body[foot] + normal3(gen, 0.005), 0.005));
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
  filter.step(input(1.0, 0.0, {}, {contact(2, foot_body[2], 0.005)}));
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
