#include <catch2/catch.hpp>
#include <lie/lie.hpp>

TEST_CASE("SE3 Log(Exp) round trip", "[lie]") {
  lie::SE3d::Tangent xi;
  xi << 0.1, -0.2, 0.3, 1.0, 2.0, 3.0;
  CHECK((lie::SE3d::Exp(xi).Log() - xi).norm() < 1e-14);
}
