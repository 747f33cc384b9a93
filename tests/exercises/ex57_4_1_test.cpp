// Exercise 57.4.1: F, B, Q, H and R of the linear KF at dt = 1 ms with FR and RL in stance,
// checked against the kit's own matrices (estimation/linear_kf/linear_kf.hpp) and hand values.
#include <catch2/catch.hpp>
#include <lie/so3.hpp>

#include "estimation/linear_kf/linear_kf.hpp"
#include "ex57_4_1.hpp"
#include "exercises/exercise_check.hpp"

namespace lkf = legkit::linear_kf;

namespace {

constexpr double kDt = 0.001;
const ex57_4_1::Stance kStance{false, true, true, false};  // FR and RL: one trot diagonal
const lkf::ContactMask kMask{false, true, true, false};

}  // namespace

TEST_CASE("57.4.1 F and B at dt = 1 ms", "[ex57.4.1][hint 1]") {
  const lkf::ProcessModel kit = lkf::processModel(kDt, kMask, lkf::ProcessNoise{});
  const ex57_4_1::Matrix18 F = ex57_4_1::F(kDt);
  const Eigen::Matrix<double, 18, 3> B = ex57_4_1::B(kDt);
  REQUIRE_NEAR(F, kit.F, 1e-18);
  REQUIRE_NEAR(B, kit.B, 1e-18);
  REQUIRE_NEAR(F(0, 3), 0.001, 0.0);
  REQUIRE_REL(B(0, 0), 5e-7, 1e-12);
  REQUIRE_NEAR(B(3, 0), 0.001, 0.0);
}

TEST_CASE("57.4.1 Q at dt = 1 ms, FR and RL in stance", "[ex57.4.1][hint 2]") {
  const ex57_4_1::Densities d;
  const lkf::ProcessNoise noise{d.accel, d.foot_stance, d.foot_swing};
  const lkf::ProcessModel kit = lkf::processModel(kDt, kMask, noise);
  const ex57_4_1::Matrix18 Q = ex57_4_1::Q(kDt, kStance, d);
  REQUIRE_NEAR(Q, kit.Q, 1e-15);
  // Hand values: vv = 1.6e-3 * 1e-3 = 1.6e-6, pv = 1.6e-3 * 1e-6 / 2 = 8e-10,
  // pp = 1.6e-3 * 1e-9 / 4 = 4e-13; stance foot 1e-6 * 1e-3 = 1e-9, swing foot 100 * 1e-3 = 0.1.
  REQUIRE_REL(Q(3, 3), 1.6e-6, 1e-12);
  REQUIRE_REL(Q(0, 3), 8e-10, 1e-12);
  REQUIRE_REL(Q(0, 0), 4e-13, 1e-12);
  REQUIRE_REL(Q(6, 6), 0.1, 1e-12);     // FL swing
  REQUIRE_REL(Q(9, 9), 1e-9, 1e-12);    // FR stance
  REQUIRE_REL(Q(12, 12), 1e-9, 1e-12);  // RL stance
  REQUIRE_REL(Q(15, 15), 0.1, 1e-12);   // RR swing
  // And with the other diagonal in stance, the feet swap.
  const ex57_4_1::Matrix18 Q2 = ex57_4_1::Q(kDt, {true, false, false, true}, d);
  REQUIRE_NEAR(Q2, lkf::processModel(kDt, {true, false, false, true}, noise).Q, 1e-15);
}

TEST_CASE("57.4.1 H of the two stance feet", "[ex57.4.1]") {
  const Eigen::MatrixXd H = ex57_4_1::H(kStance);
  Eigen::MatrixXd kit(6, 18);
  kit << lkf::footMeasurementMatrix(1), lkf::footMeasurementMatrix(2);
  REQUIRE_NEAR(H, kit, 0.0);
  REQUIRE_NEAR(ex57_4_1::H({true, true, true, true}).rows(), 12, 0.0);
  REQUIRE_NEAR(ex57_4_1::H({false, false, false, false}).rows(), 0, 0.0);
}

TEST_CASE("57.4.1 R of the two stance feet, with the shared attitude error", "[ex57.4.1][hint 3]") {
  const Eigen::Matrix3d R_hat = lie::SO3d::Exp(Eigen::Vector3d(0.02, -0.03, 0.8)).matrix();
  const std::array<Eigen::Vector3d, 4> r{
      Eigen::Vector3d(0.19, 0.14, -0.30), Eigen::Vector3d(0.20, -0.15, -0.31),
      Eigen::Vector3d(-0.18, 0.14, -0.29), Eigen::Vector3d(-0.19, -0.13, -0.30)};
  std::array<Eigen::Matrix3d, 4> C;
  for (int i = 0; i < 4; ++i) {
    C[i] = Eigen::Vector3d(2.5e-5, 2.6e-5, 2.7e-5 + 1e-6 * i).asDiagonal();
    C[i](0, 2) = C[i](2, 0) = 2e-6;
  }
  const Eigen::Matrix3d Sigma_theta = Eigen::Vector3d(1e-5, 1e-5, 4e-5).asDiagonal();
  const Eigen::MatrixXd Rn = ex57_4_1::R(kStance, R_hat, r, C, Sigma_theta);
  // The kit's blocks: FR (1) first, RL (2) second.
  Eigen::MatrixXd kit(6, 6);
  kit << lkf::footMeasurementNoise(R_hat, r[1], C[1], Sigma_theta),
      lkf::attitudeNoiseBlock(R_hat * r[1], R_hat * r[2], Sigma_theta),
      lkf::attitudeNoiseBlock(R_hat * r[2], R_hat * r[1], Sigma_theta),
      lkf::footMeasurementNoise(R_hat, r[2], C[2], Sigma_theta);
  REQUIRE_NEAR(Rn, kit, 1e-18);
  REQUIRE_NEAR(Rn, Rn.transpose(), 1e-20);
  // Hand value of one cross entry with R_hat = I and Sigma_theta = s I:
  // ([a]_x [b]_x^T)(0, 0) = a_y b_y + a_z b_z for a = r_FR, b = r_RL.
  const double s = 1e-5;
  const Eigen::MatrixXd Ri =
      ex57_4_1::R(kStance, Eigen::Matrix3d::Identity(), r, C, s * Eigen::Matrix3d::Identity());
  REQUIRE_REL(Ri(0, 3), s * (-0.15 * 0.14 + -0.31 * -0.29), 1e-12);
  // Without attitude error the feet are independent and R is their own covariances.
  const Eigen::MatrixXd R0 =
      ex57_4_1::R(kStance, Eigen::Matrix3d::Identity(), r, C, Eigen::Matrix3d::Zero());
  REQUIRE_NEAR((R0.topRightCorner<3, 3>()), Eigen::Matrix3d::Zero(), 0.0);
  REQUIRE_NEAR((R0.topLeftCorner<3, 3>()), C[1], 1e-20);
  REQUIRE_NEAR((R0.bottomRightCorner<3, 3>()), C[2], 1e-20);
}
