// Exercise 57.5.3: the ESKF's F against the kit's ESKF, the InEKF's A against the limit of the
// exact InEKF transition of lie/imu_dynamics.hpp, and what each depends on.
#include <catch2/catch.hpp>
#include <lie/imu_dynamics.hpp>
#include <lie/sek3.hpp>
#include <random>

#include "estimation/invariant/eskf.hpp"
#include "ex57_5_3.hpp"
#include "exercises/exercise_check.hpp"

using ex57_5_3::BlockCount;
using ex57_5_3::Matrix15;
using ex57_5_3::NavState;

namespace {

const Eigen::Vector3d kGravity(0.0, 0.0, -9.81);

Eigen::Vector3d normal3(std::mt19937& gen, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  return {n(gen), n(gen), n(gen)};
}

NavState randomState(std::mt19937& gen) {
  NavState x;
  x.R = lie::SO3d::Random(gen).matrix();
  x.v = normal3(gen, 1.0);
  x.p = normal3(gen, 2.0);
  x.b_g = normal3(gen, 0.05);
  x.b_a = normal3(gen, 0.3);
  return x;
}

// The kit's ESKF F (27 x 27) restricted to the navigation and bias blocks, in this exercise's
// order (dtheta, dv, dp, db_g, db_a).
Matrix15 kitEskfF(const NavState& x, const Eigen::Vector3d& w_m, const Eigen::Vector3d& a_m) {
  namespace eskf = legkit::invariant::eskf;
  eskf::State s;
  s.R = lie::SO3d::fromMatrix(x.R, 1e-9);
  s.v = x.v;
  s.p = x.p;
  s.b_g = x.b_g;
  s.b_a = x.b_a;
  const eskf::Matrix27 F = eskf::errorDynamics(s, {w_m, a_m});
  const std::array<int, 5> at = {eskf::kTheta, eskf::kV, eskf::kP, eskf::kBg, eskf::kBa};
  Matrix15 J;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) J.block<3, 3>(3 * i, 3 * j) = F.block<3, 3>(at[i], at[j]);
  return J;
}

Matrix15 zeroBiasColumns(Matrix15 J) {
  J.rightCols<6>().setZero();
  return J;
}

}  // namespace

TEST_CASE("57.5.3 eskfF is the ESKF's error dynamics", "[ex57.5.3][hint 1]") {
  std::mt19937 gen(1);
  for (int trial = 0; trial < 50; ++trial) {
    const NavState x = randomState(gen);
    const Eigen::Vector3d w_m = normal3(gen, 2.0), a_m = normal3(gen, 10.0);
    const Matrix15 F = ex57_5_3::eskfF(x, w_m, a_m);
    REQUIRE_NEAR(F, kitEskfF(x, w_m, a_m), 1e-12);
  }
}

TEST_CASE("57.5.3 eskfF depends on the estimate and on the measured input", "[ex57.5.3][hint 1]") {
  // By hand: level, no bias, at rest (a_m = +g up): the dv-dtheta block is -[a_m]_x.
  const Eigen::Vector3d w_m = Eigen::Vector3d::Zero(), a_m(0.0, 0.0, 9.81);
  NavState level;
  Eigen::Matrix3d expected;
  expected << 0.0, 9.81, 0.0, -9.81, 0.0, 0.0, 0.0, 0.0, 0.0;
  const Matrix15 F_level = ex57_5_3::eskfF(level, w_m, a_m);
  const Eigen::Matrix3d dv_dtheta_level = F_level.block<3, 3>(3, 0);
  REQUIRE_NEAR(dv_dtheta_level, expected, 1e-12);
  // The same motion seen from an estimate turned 90 degrees about x: the block turns with R_hat.
  NavState turned = level;
  turned.R = lie::SO3d::Exp(Eigen::Vector3d(M_PI / 2, 0.0, 0.0)).matrix();
  const Matrix15 F_turned = ex57_5_3::eskfF(turned, w_m, a_m);
  const Eigen::Matrix3d dv_dtheta_turned = F_turned.block<3, 3>(3, 0);
  REQUIRE_NEAR(dv_dtheta_turned, turned.R * expected, 1e-12);
  REQUIRE_ABOVE((F_turned - F_level).norm(), 10.0);
  // Another gyro reading or gyro-bias estimate changes the attitude block.
  REQUIRE_ABOVE((ex57_5_3::eskfF(level, Eigen::Vector3d(0.0, 0.0, 1.0), a_m) - F_level).norm(),
                1.0);
  NavState biased = level;
  biased.b_g = Eigen::Vector3d(0.01, 0.0, 0.0);
  REQUIRE_ABOVE((ex57_5_3::eskfF(biased, w_m, a_m) - F_level).norm(), 0.01);
}

TEST_CASE("57.5.3 inekfA is the rate of the InEKF's exact transition", "[ex57.5.3][hint 2]") {
  // lie::imu::phiWithBias is the exact discrete transition of the imperfect InEKF over h:
  // Phi(h) = I + A h + O(h^2), so (Phi(h) - I) / h tends to A.
  std::mt19937 gen(2);
  const double h = 1e-6;
  for (int trial = 0; trial < 30; ++trial) {
    const NavState x0 = randomState(gen);
    const Eigen::Vector3d w = normal3(gen, 2.0), a = normal3(gen, 10.0);
    lie::SE23d::Columns C;
    C << x0.v, x0.p;
    const lie::SE23d X =
        lie::imu::propagate(lie::SE23d(lie::SO3d::fromMatrix(x0.R, 1e-9), C), w, a, kGravity, h);
    NavState x = x0;
    x.R = X.R();
    x.v = X.col(0);
    x.p = X.col(1);
    const Matrix15 rate = (lie::imu::phiWithBias(X, w, a, kGravity, h) - Matrix15::Identity()) / h;
    const Matrix15 A = ex57_5_3::inekfA(x, kGravity);
    INFO("trial " << trial);
    REQUIRE_NEAR(A, rate, 1e-4 * (1.0 + A.cwiseAbs().maxCoeff()));
  }
}

TEST_CASE("57.5.3 inekfA: the navigation block is constant, the bias block is not",
          "[ex57.5.3][hint 2]") {
  std::mt19937 gen(3);
  Eigen::Matrix<double, 9, 9> A_t = Eigen::Matrix<double, 9, 9>::Zero();
  A_t.block<3, 3>(3, 0) << 0.0, 9.81, 0.0, -9.81, 0.0, 0.0, 0.0, 0.0, 0.0;  // [g]_x
  A_t.block<3, 3>(6, 3).setIdentity();
  for (int trial = 0; trial < 20; ++trial) {
    const NavState x1 = randomState(gen), x2 = randomState(gen);
    const Matrix15 A1 = ex57_5_3::inekfA(x1, kGravity), A2 = ex57_5_3::inekfA(x2, kGravity);
    const Eigen::Matrix<double, 9, 9> A1_nav = A1.topLeftCorner<9, 9>();
    const Eigen::Matrix<double, 9, 9> A2_nav = A2.topLeftCorner<9, 9>();
    REQUIRE_NEAR(A1_nav, A_t, 1e-12);
    REQUIRE_NEAR(A2_nav, A_t, 1e-12);
    REQUIRE_ABOVE((A1.topRightCorner<9, 6>() - A2.topRightCorner<9, 6>()).norm(), 0.1);
    REQUIRE(A1.bottomRows<6>().norm() == 0.0);
  }
}

TEST_CASE("57.5.3 countBlocks on matrices made by hand", "[ex57.5.3]") {
  const Matrix15 Z = Matrix15::Zero(), I = Matrix15::Identity();
  BlockCount c = ex57_5_3::countBlocks(Z, Z);
  REQUIRE(c.nonzero == 0);
  REQUIRE(c.estimate_dependent == 0);
  c = ex57_5_3::countBlocks(I, I);
  REQUIRE(c.nonzero == 5);
  REQUIRE(c.estimate_dependent == 0);
  Matrix15 J = I;
  J(4, 13) = 2.0;  // block (1, 4) appears at the second estimate only
  J(0, 0) = 3.0;   // block (0, 0) changes
  c = ex57_5_3::countBlocks(I, J);
  REQUIRE(c.nonzero == 6);
  REQUIRE(c.estimate_dependent == 2);
  Matrix15 tiny = I;
  tiny(7, 2) = 1e-14;  // below the tolerance: neither non-zero nor a change
  c = ex57_5_3::countBlocks(I, tiny);
  REQUIRE(c.nonzero == 5);
  REQUIRE(c.estimate_dependent == 0);
}

TEST_CASE("57.5.3 what each Jacobian depends on, block by block", "[ex57.5.3]") {
  std::mt19937 gen(4);
  const NavState x1 = randomState(gen), x2 = randomState(gen);
  const Eigen::Vector3d w_m = normal3(gen, 2.0), a_m = normal3(gen, 10.0);
  const Matrix15 F1 = ex57_5_3::eskfF(x1, w_m, a_m), F2 = ex57_5_3::eskfF(x2, w_m, a_m);
  const Matrix15 A1 = ex57_5_3::inekfA(x1, kGravity), A2 = ex57_5_3::inekfA(x2, kGravity);
  // ESKF: 5 non-zero blocks, 3 of them move with the estimate (attitude-attitude through b_g,
  // velocity-attitude through R and b_a, velocity-accel-bias through R).
  const BlockCount eskf = ex57_5_3::countBlocks(F1, F2);
  REQUIRE(eskf.nonzero == 5);
  REQUIRE(eskf.estimate_dependent == 3);
  // Imperfect InEKF: 6 non-zero blocks, the 4 bias couplings move with the estimate...
  const BlockCount inekf = ex57_5_3::countBlocks(A1, A2);
  REQUIRE(inekf.nonzero == 6);
  REQUIRE(inekf.estimate_dependent == 4);
  // ...but on the navigation block (without the bias columns) the ESKF keeps 2 estimate-dependent
  // blocks and the InEKF none: that is the "autonomous error" of the section.
  REQUIRE(ex57_5_3::countBlocks(zeroBiasColumns(F1), zeroBiasColumns(F2)).estimate_dependent == 2);
  REQUIRE(ex57_5_3::countBlocks(zeroBiasColumns(A1), zeroBiasColumns(A2)).estimate_dependent == 0);
}
