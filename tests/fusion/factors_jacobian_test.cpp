// The smoother's factors (section 57.8): every analytic Jacobian against Ceres's central
// differences taken through the SO3 manifold's Plus, at random states with small and large
// rotations. The analytic ambient Jacobian of a rotation block times PlusJacobian must equal the
// numeric tangent Jacobian: |J_num - J_a P|_max <= 1e-8 max(1, |J_num|_max) per block (measured: at
// most 6.5e-10).
#include <ceres/dynamic_numeric_diff_cost_function.h>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "estimation/fusion/factors.hpp"
#include "lie/ceres/manifolds.hpp"
#include "lie/so3.hpp"

#include "ceres_catch.hpp"  // after Ceres: Catch's CHECK, not glog's

using Eigen::Matrix3d;
using Eigen::Vector3d;
using legkit::fusion::ambientJacobian;
using legkit::fusion::BiasWalkFactor;
using legkit::fusion::ImuFactor;
using legkit::fusion::LegOdometryFactor;
using legkit::fusion::LegPreintegrator;
using legkit::fusion::PoseFactor;
using legkit::fusion::PoseMeasurement;
using legkit::imu::Preintegrator;
using legkit::model::ImuBias;
using legkit::model::ImuReading;
using RowMajorDyn = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

namespace {

constexpr double kDt = 1e-3;
constexpr double kTol = 1e-8;

const lie::ceres::SO3Manifold kSO3;

// The factor seen as a function of tangent increments: rotation blocks through Plus, the others
// added. Ceres steps by relative_step_size |d| (at least sqrt(eps) = 1.5e-8 at d = 0), so the
// increment is offset by one, d = 1 + delta, and differentiated at d = 1: its central-difference
// Jacobian there is the tangent Jacobian at x, taken with steps of relative_step_size.
struct TangentProbe {
  const ceres::CostFunction* f;
  std::vector<std::vector<double>> x;
  std::vector<bool> rotation;
  bool operator()(double const* const* d, double* r) const {
    std::vector<std::vector<double>> xd = x;
    std::vector<const double*> ptr;
    for (size_t b = 0; b < x.size(); ++b) {
      const int t = rotation[b] ? 3 : static_cast<int>(x[b].size());
      std::vector<double> delta(d[b], d[b] + t);
      for (double& e : delta) e -= 1.0;
      if (rotation[b]) {
        kSO3.Plus(x[b].data(), delta.data(), xd[b].data());
      } else {
        for (int k = 0; k < t; ++k) xd[b][k] += delta[k];
      }
      ptr.push_back(xd[b].data());
    }
    return f->Evaluate(ptr.data(), r, nullptr);
  }
};

// Returns the worst per-block relative error of the analytic tangent Jacobians.
double worstJacobianError(const ceres::CostFunction& f, const std::vector<std::vector<double>>& x,
                          const std::vector<bool>& rotation) {
  const int m = f.num_residuals();
  const size_t nb = x.size();
  REQUIRE(f.parameter_block_sizes().size() == nb);

  std::vector<const double*> xp;
  std::vector<RowMajorDyn> J_a;
  std::vector<double*> J_ptr;
  for (size_t b = 0; b < nb; ++b) {
    xp.push_back(x[b].data());
    J_a.emplace_back(m, static_cast<int>(x[b].size()));
    J_ptr.push_back(J_a.back().data());
  }
  Eigen::VectorXd r(m), r_plain(m);
  REQUIRE(f.Evaluate(xp.data(), r.data(), J_ptr.data()));
  REQUIRE(f.Evaluate(xp.data(), r_plain.data(), nullptr));
  CHECK((r - r_plain).norm() == 0.0);  // the residual does not depend on asking for Jacobians

  auto* probe = new TangentProbe{&f, x, rotation};
  // Step 1e-5, near eps^(1/3), the best for central differences (Ceres's default is 1e-6).
  ceres::NumericDiffOptions options;
  options.relative_step_size = 1e-5;
  ceres::DynamicNumericDiffCostFunction<TangentProbe, ceres::CENTRAL> numeric(
      probe, ceres::TAKE_OWNERSHIP, options);
  std::vector<std::vector<double>> origin;
  std::vector<const double*> zp;
  std::vector<RowMajorDyn> J_n;
  std::vector<double*> Jn_ptr;
  for (size_t b = 0; b < nb; ++b) {
    const int t = rotation[b] ? 3 : static_cast<int>(x[b].size());
    numeric.AddParameterBlock(t);
    origin.emplace_back(t, 1.0);  // delta = 0
    J_n.emplace_back(m, t);
  }
  for (size_t b = 0; b < nb; ++b) {
    zp.push_back(origin[b].data());
    Jn_ptr.push_back(J_n[b].data());
  }
  numeric.SetNumResiduals(m);
  Eigen::VectorXd r_n(m);
  REQUIRE(numeric.Evaluate(zp.data(), r_n.data(), Jn_ptr.data()));
  CHECK((r_n - r).norm() <= 1e-12 * (1.0 + r.norm()));

  double worst = 0.0;
  for (size_t b = 0; b < nb; ++b) {
    RowMajorDyn J_t = J_a[b];
    if (rotation[b]) {
      Eigen::Matrix<double, 9, 3, Eigen::RowMajor> P;
      kSO3.PlusJacobian(x[b].data(), P.data());
      J_t = J_a[b] * P;
    }
    const double scale = std::max(1.0, J_n[b].cwiseAbs().maxCoeff());
    const double err = (J_t - J_n[b]).cwiseAbs().maxCoeff() / scale;
    INFO("block " << b << " analytic\n" << J_t << "\nnumeric\n" << J_n[b]);
    CHECK(err <= kTol);
    worst = std::max(worst, err);
  }
  return worst;
}

std::vector<double> blockOf(const Matrix3d& R) {
  return {R.data(), R.data() + 9};
}
std::vector<double> blockOf(const Vector3d& v) {
  return {v.data(), v.data() + 3};
}

Vector3d randomVector(std::mt19937_64& gen, double scale) {
  std::normal_distribution<double> n01(0.0, 1.0);
  return scale * Vector3d(n01(gen), n01(gen), n01(gen));
}

// A rotation vector of the given angle along a random axis.
Vector3d randomAngle(std::mt19937_64& gen, double angle) {
  return angle * randomVector(gen, 1.0).normalized();
}

// Readings of a lively motion (trot-like rates and specific forces) over n samples.
std::vector<ImuReading> lively(std::mt19937_64& gen, int n) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Vector3d w0(u(gen), u(gen), u(gen)), a0(u(gen), u(gen), 9.81 + u(gen));
  std::vector<ImuReading> m(n);
  for (int k = 0; k < n; ++k) {
    const double t = k * kDt;
    m[k].w_m = w0 + 1.5 * Vector3d(std::sin(5 * t), std::cos(4 * t), std::sin(2 * t + 1.0));
    m[k].a_m = a0 + 3.0 * Vector3d(std::cos(4 * t), std::sin(2 * t), std::sin(5 * t));
  }
  return m;
}

// The angles of the random states: near zero, moderate, and large (up to 0.9 pi).
const double kAngles[] = {1e-7, 1e-3, 0.3, 1.5, 2.8};

}  // namespace

TEST_CASE("57.8 ambientJacobian times the SO3 PlusJacobian is the tangent Jacobian", "[factors]") {
  std::mt19937_64 gen(11);
  for (int trial = 0; trial < 20; ++trial) {
    const Matrix3d R = lie::SO3d::Random(gen).matrix();
    Eigen::Matrix<double, 6, 3> J_t;
    J_t.setRandom();
    Eigen::Matrix<double, 9, 3, Eigen::RowMajor> P;
    kSO3.PlusJacobian(R.data(), P.data());
    CHECK((ambientJacobian(J_t, R) * P - J_t).cwiseAbs().maxCoeff() <= 1e-14);
    const Eigen::Matrix<double, 1, 3> row = J_t.row(0);
    CHECK((ambientJacobian(row, R) * P - row).cwiseAbs().maxCoeff() <= 1e-14);
  }
}

TEST_CASE("57.8 ImuFactor: analytic Jacobians equal central differences", "[factors]") {
  std::mt19937_64 gen(20261124);
  double worst = 0.0;
  for (const double angle : kAngles) {
    for (int trial = 0; trial < 4; ++trial) {
      ImuBias b0;
      b0.b_g = randomVector(gen, 0.02);
      b0.b_a = randomVector(gen, 0.1);
      Preintegrator pim(b0);
      for (const ImuReading& m : lively(gen, 100)) pim.integrate(m, kDt);
      const ImuFactor f(pim, legkit::model::gravity());

      // R_i anywhere; R_j = R_i dR Exp(xi) with |xi| = angle, so that r_phi has that size; v_j,
      // p_j 0.1 m/s, 0.1 m off the prediction (the whitened residuals stay below ~1e5: farther,
      // the rounding of central differences, eps |r| / step, exceeds the tolerance).
      const legkit::imu::NavState x_i{lie::SO3d::Random(gen), randomVector(gen, 1.0),
                                      randomVector(gen, 5.0)};
      const Matrix3d R_i = x_i.R.matrix();
      const legkit::imu::NavState x_j = pim.predict(x_i, b0);
      const Matrix3d R_j = x_j.R.matrix() * lie::SO3d::Exp(randomAngle(gen, angle)).matrix();
      const std::vector<std::vector<double>> x = {
          blockOf(R_i),
          blockOf(x_i.v),
          blockOf(x_i.p),
          blockOf(R_j),
          blockOf(Vector3d(x_j.v + randomVector(gen, 0.1))),
          blockOf(Vector3d(x_j.p + randomVector(gen, 0.1))),
          blockOf(Vector3d(b0.b_g + randomVector(gen, 0.01))),
          blockOf(Vector3d(b0.b_a + randomVector(gen, 0.05)))};
      worst = std::max(
          worst, worstJacobianError(f, x, {true, false, false, true, false, false, false, false}));
    }
  }
  WARN("ImuFactor worst relative Jacobian error " << worst);
}

TEST_CASE("57.8 PoseFactor: analytic Jacobians equal central differences", "[factors]") {
  std::mt19937_64 gen(7);
  double worst = 0.0;
  for (const double angle : kAngles) {
    for (int trial = 0; trial < 4; ++trial) {
      PoseMeasurement z;
      z.R_MB = lie::SO3d::Random(gen);
      z.p_MB = randomVector(gen, 10.0);
      Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Random();
      z.cov = 1e-3 * (A * A.transpose() + 0.1 * Eigen::Matrix<double, 6, 6>::Identity());
      const PoseFactor f(z);
      // The state's attitude is Exp(-xi) R_meas, so that Log(R_meas R^T) = xi has size angle.
      const Matrix3d R = lie::SO3d::Exp(-randomAngle(gen, angle)).matrix() * z.R_MB.matrix();
      const std::vector<std::vector<double>> x = {
          blockOf(R), blockOf(Vector3d(z.p_MB + randomVector(gen, 0.1)))};
      worst = std::max(worst, worstJacobianError(f, x, {true, false}));
    }
  }
  WARN("PoseFactor worst relative Jacobian error " << worst);
}

TEST_CASE("57.8 BiasWalkFactor: residual and Jacobians", "[factors]") {
  std::mt19937_64 gen(3);
  const BiasWalkFactor f(5e-5, 0.1);
  const Vector3d b_i = randomVector(gen, 0.01), b_j = randomVector(gen, 0.01);
  const double* x[] = {b_i.data(), b_j.data()};
  Vector3d r;
  REQUIRE(f.Evaluate(x, r.data(), nullptr));
  CHECK((r - (b_j - b_i) / (5e-5 * std::sqrt(0.1))).norm() <= 1e-9 * r.norm());
  const double worst = worstJacobianError(f, {blockOf(b_i), blockOf(b_j)}, {false, false});
  CHECK(worst <= kTol);
  CHECK_THROWS_AS(BiasWalkFactor(0.0, 0.1), std::invalid_argument);
  CHECK_THROWS_AS(BiasWalkFactor(1e-4, -0.1), std::invalid_argument);
  CHECK_THROWS_AS(BiasWalkFactor(NAN, 0.1), std::invalid_argument);
}

TEST_CASE("57.8 LegOdometryFactor: analytic Jacobians equal central differences", "[factors]") {
  std::mt19937_64 gen(5);
  double worst = 0.0;
  for (const double angle : kAngles) {
    for (int trial = 0; trial < 4; ++trial) {
      const Vector3d b_g0 = randomVector(gen, 0.02), b_v0 = randomVector(gen, 0.05);
      LegPreintegrator lpi(b_g0, b_v0);
      const Matrix3d Sigma_v = Vector3d(0.01, 0.02, 0.015).asDiagonal();
      for (const ImuReading& m : lively(gen, 100)) {
        lpi.integrate(m.w_m, Vector3d(0.8, 0.1, 0.0) + 0.1 * m.a_m, Sigma_v, kDt);
      }
      const LegOdometryFactor f(lpi);
      const Matrix3d R_i = lie::SO3d::Exp(randomAngle(gen, angle)).matrix();
      const Vector3d p_i = randomVector(gen, 5.0);
      const Vector3d p_j = p_i + R_i * lpi.dp() + randomVector(gen, 0.01);
      const std::vector<std::vector<double>> x = {
          blockOf(R_i), blockOf(p_i), blockOf(p_j),
          blockOf(Vector3d(b_v0 + randomVector(gen, 0.02))),
          blockOf(Vector3d(b_g0 + randomVector(gen, 0.01)))};
      worst = std::max(worst, worstJacobianError(f, x, {true, false, false, false, false}));
    }
  }
  WARN("LegOdometryFactor worst relative Jacobian error " << worst);
}

TEST_CASE("57.8 factors refuse a covariance they cannot whiten", "[factors]") {
  PoseMeasurement z;
  z.cov(2, 2) = -1.0;
  CHECK_THROWS_AS(PoseFactor(z), std::invalid_argument);
  z.cov = Eigen::Matrix<double, 6, 6>::Identity();
  z.cov(0, 1) = 0.5;  // not symmetric
  CHECK_THROWS_AS(PoseFactor(z), std::invalid_argument);
  z.cov = Eigen::Matrix<double, 6, 6>::Identity();
  z.valid = false;
  CHECK_THROWS_AS(PoseFactor(z), std::invalid_argument);
  z.valid = true;
  z.p_MB.x() = NAN;
  CHECK_THROWS_AS(PoseFactor(z), std::invalid_argument);

  // No sample: a zero covariance.
  CHECK_THROWS_AS(ImuFactor(Preintegrator(), legkit::model::gravity()), std::invalid_argument);
  CHECK_THROWS_AS(LegOdometryFactor(LegPreintegrator()), std::invalid_argument);
  Preintegrator pim;  // one sample leaves (dv, dp) perfectly correlated: ten make it definite
  for (int k = 0; k < 10; ++k)
    pim.integrate(ImuReading{Vector3d::Zero(), Vector3d(0, 0, 9.81)}, kDt);
  CHECK_THROWS_AS(ImuFactor(pim, Vector3d(0, 0, NAN)), std::invalid_argument);
  CHECK_NOTHROW(ImuFactor(pim, legkit::model::gravity()));
}
