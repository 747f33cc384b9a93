// Exercise 57.4.1: F, B, Q, H and R of the linear KF at dt = 1 ms with FR and RL in stance,
// checked against the kit's own matrices (estimation/linear_kf/linear_kf.hpp) and hand values.
#include <catch2/catch.hpp>
#include <lie/so3.hpp>

#include "estimation/linear_kf/linear_kf.hpp"
#include "ex57_4_1.hpp"

namespace lkf = legkit::linear_kf;

namespace {

constexpr double kDt = 0.001;
const ex57_4_1::Stance kStance{false, true, true, false};  // FR and RL: one trot diagonal
const lkf::ContactMask kMask{false, true, true, false};

double maxAbs(const Eigen::MatrixXd& A) {
  return A.cwiseAbs().maxCoeff();
}

}  // namespace

TEST_CASE("57.4.1 F and B at dt = 1 ms", "[ex57.4.1]") {
  const lkf::ProcessModel kit = lkf::processModel(kDt, kMask, lkf::ProcessNoise{});
  const ex57_4_1::Matrix18 F = ex57_4_1::F(kDt);
  const Eigen::Matrix<double, 18, 3> B = ex57_4_1::B(kDt);
  CHECK(maxAbs(F - kit.F) < 1e-18);
  CHECK(maxAbs(B - kit.B) < 1e-18);
  CHECK(F(0, 3) == 0.001);
  CHECK(B(0, 0) == Approx(5e-7));
  CHECK(B(3, 0) == 0.001);
}

TEST_CASE("57.4.1 Q at dt = 1 ms, FR and RL in stance", "[ex57.4.1]") {
  const ex57_4_1::Densities d;
  const lkf::ProcessNoise noise{d.accel, d.foot_stance, d.foot_swing};
  const lkf::ProcessModel kit = lkf::processModel(kDt, kMask, noise);
  const ex57_4_1::Matrix18 Q = ex57_4_1::Q(kDt, kStance, d);
  CHECK(maxAbs(Q - kit.Q) < 1e-15);
  // Hand values: vv = 1.6e-3 * 1e-3 = 1.6e-6, pv = 1.6e-3 * 1e-6 / 2 = 8e-10,
  // pp = 1.6e-3 * 1e-9 / 4 = 4e-13; stance foot 1e-6 * 1e-3 = 1e-9, swing foot 100 * 1e-3 = 0.1.
  CHECK(Q(3, 3) == Approx(1.6e-6));
  CHECK(Q(0, 3) == Approx(8e-10));
  CHECK(Q(0, 0) == Approx(4e-13));
  CHECK(Q(6, 6) == Approx(0.1));     // FL swing
  CHECK(Q(9, 9) == Approx(1e-9));    // FR stance
  CHECK(Q(12, 12) == Approx(1e-9));  // RL stance
  CHECK(Q(15, 15) == Approx(0.1));   // RR swing
  // And with the other diagonal in stance, the feet swap.
  const ex57_4_1::Matrix18 Q2 = ex57_4_1::Q(kDt, {true, false, false, true}, d);
  CHECK(maxAbs(Q2 - lkf::processModel(kDt, {true, false, false, true}, noise).Q) < 1e-15);
}

TEST_CASE("57.4.1 H of the two stance feet", "[ex57.4.1]") {
  const Eigen::MatrixXd H = ex57_4_1::H(kStance);
  REQUIRE(H.rows() == 6);
  REQUIRE(H.cols() == 18);
  CHECK(maxAbs(H.topRows<3>() - lkf::footMeasurementMatrix(1)) == 0.0);
  CHECK(maxAbs(H.bottomRows<3>() - lkf::footMeasurementMatrix(2)) == 0.0);
  CHECK(ex57_4_1::H({true, true, true, true}).rows() == 12);
  CHECK(ex57_4_1::H({false, false, false, false}).rows() == 0);
}

TEST_CASE("57.4.1 R of the two stance feet", "[ex57.4.1]") {
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
  REQUIRE(Rn.rows() == 6);
  REQUIRE(Rn.cols() == 6);
  CHECK(maxAbs(Rn.topLeftCorner<3, 3>() -
               lkf::footMeasurementNoise(R_hat, r[1], C[1], Sigma_theta)) < 1e-18);
  CHECK(maxAbs(Rn.bottomRightCorner<3, 3>() -
               lkf::footMeasurementNoise(R_hat, r[2], C[2], Sigma_theta)) < 1e-18);
  CHECK(maxAbs(Rn.topRightCorner<3, 3>()) == 0.0);
  // Without attitude error and with R_hat = I, R is the feet's own covariance.
  const Eigen::MatrixXd R0 =
      ex57_4_1::R(kStance, Eigen::Matrix3d::Identity(), r, C, Eigen::Matrix3d::Zero());
  CHECK(maxAbs(R0.topLeftCorner<3, 3>() - C[1]) < 1e-20);
}
