// Exercise 57.5.1: SE_2(3) product and inverse, checked against the 5x5 matrix algebra and
// against lie::SE23d.
#include <catch2/catch.hpp>
#include <lie/sek3.hpp>
#include <random>

#include "ex57_5_1.hpp"
#include "exercises/exercise_check.hpp"

using ex57_5_1::ExtendedPose;
using ex57_5_1::Matrix5d;

namespace {

ExtendedPose randomPose(std::mt19937& gen) {
  const lie::SE23d X = lie::SE23d::Random(gen, 3.0);
  return {X.R(), X.col(0), X.col(1)};
}

lie::SE23d toLie(const ExtendedPose& X) {
  lie::SE23d::Columns C;
  C << X.v, X.p;
  return lie::SE23d(lie::SO3d::fromMatrix(X.R), C);
}

}  // namespace

TEST_CASE("57.5.1 toMatrix places R, v and p in the 5x5 matrix", "[ex57.5.1][hint 1]") {
  std::mt19937 gen(1);
  const ExtendedPose X = randomPose(gen);
  const Matrix5d expected = toLie(X).matrix();
  REQUIRE_NEAR(ex57_5_1::toMatrix(X), expected, 1e-15 * expected.norm());
}

TEST_CASE("57.5.1 compose equals the matrix product and stays in SE_2(3)", "[ex57.5.1][hint 1]") {
  std::mt19937 gen(2);
  for (int i = 0; i < 50; ++i) {
    const ExtendedPose A = randomPose(gen), B = randomPose(gen);
    const ExtendedPose AB = ex57_5_1::compose(A, B);
    const Matrix5d expected = ex57_5_1::toMatrix(A) * ex57_5_1::toMatrix(B);
    REQUIRE_NEAR(ex57_5_1::toMatrix(AB), expected, 1e-12);
    REQUIRE(toLie(AB).isApprox(toLie(A) * toLie(B), 1e-12));
    REQUIRE(ex57_5_1::isInSE23(ex57_5_1::toMatrix(AB), 1e-9));
  }
}

TEST_CASE("57.5.1 inverse undoes compose on both sides and stays in SE_2(3)",
          "[ex57.5.1][hint 1]") {
  std::mt19937 gen(3);
  for (int i = 0; i < 50; ++i) {
    const ExtendedPose X = randomPose(gen);
    const ExtendedPose Xi = ex57_5_1::inverse(X);
    REQUIRE_NEAR(ex57_5_1::toMatrix(ex57_5_1::compose(X, Xi)), Matrix5d::Identity(), 1e-12);
    REQUIRE_NEAR(ex57_5_1::toMatrix(ex57_5_1::compose(Xi, X)), Matrix5d::Identity(), 1e-12);
    REQUIRE(ex57_5_1::isInSE23(ex57_5_1::toMatrix(Xi), 1e-9));
  }
}

TEST_CASE("57.5.1 isInSE23 rejects matrices outside the group", "[ex57.5.1][hint 2]") {
  std::mt19937 gen(4);
  const Matrix5d good = ex57_5_1::toMatrix(randomPose(gen));
  REQUIRE(ex57_5_1::isInSE23(good, 1e-9));

  Matrix5d reflection = good;
  reflection.col(0) *= -1.0;  // det R = -1
  REQUIRE_FALSE(ex57_5_1::isInSE23(reflection, 1e-9));

  Matrix5d stretched = good;
  stretched.topLeftCorner<3, 3>() *= 1.01;  // not orthonormal
  REQUIRE_FALSE(ex57_5_1::isInSE23(stretched, 1e-9));

  Matrix5d wrongBottom = good;
  wrongBottom(3, 0) = 0.5;  // last rows must be [0 | I]
  REQUIRE_FALSE(ex57_5_1::isInSE23(wrongBottom, 1e-9));

  Matrix5d notANumber = good;
  notANumber(0, 3) = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_FALSE(ex57_5_1::isInSE23(notANumber, 1e-9));
}
