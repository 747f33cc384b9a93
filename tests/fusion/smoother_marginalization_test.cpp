// Marginalisation by the Schur complement (estimation/fusion/marginalization.hpp): on a linear-
// Gaussian problem the prior reproduces the exact marginal (information and mean); on a nonlinear
// problem with a manifold block, solving with the prior agrees with solving the whole problem to
// first order in the distance between the linearisation point and the optimum.
#include <ceres/autodiff_cost_function.h>
#include <ceres/crs_matrix.h>
#include <ceres/rotation.h>
#include <ceres/solver.h>
#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <random>

#include "estimation/fusion/marginalization.hpp"

#include "ceres_catch.hpp"  // after Ceres: Catch's CHECK, not glog's

namespace {

using legkit::fusion::LinearPrior;
using legkit::fusion::marginalizeOut;
using legkit::fusion::marginalPrior;

// r = sum_i A_i x_i - c over any number of Euclidean blocks.
class LinearFactor final : public ceres::CostFunction {
 public:
  LinearFactor(std::vector<Eigen::MatrixXd> A, Eigen::VectorXd c) : A_(std::move(A)), c_(c) {
    set_num_residuals(static_cast<int>(c_.size()));
    for (const auto& a : A_) mutable_parameter_block_sizes()->push_back(static_cast<int>(a.cols()));
  }
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    Eigen::Map<Eigen::VectorXd> r(residuals, c_.size());
    r = -c_;
    for (std::size_t i = 0; i < A_.size(); ++i) {
      r += A_[i] * Eigen::Map<const Eigen::VectorXd>(x[i], A_[i].cols());
      if (jacobians && jacobians[i])
        Eigen::Map<Eigen::Matrix<double, -1, -1, Eigen::RowMajor>>(jacobians[i], A_[i].rows(),
                                                                   A_[i].cols()) = A_[i];
    }
    return true;
  }

 private:
  std::vector<Eigen::MatrixXd> A_;
  Eigen::VectorXd c_;
};

Eigen::MatrixXd randomMatrix(int rows, int cols, std::mt19937& gen) {
  std::normal_distribution<double> n;
  Eigen::MatrixXd M(rows, cols);
  for (int i = 0; i < M.size(); ++i) M.data()[i] = n(gen);
  return M;
}

// The Jacobian of the residual blocks of `problem` at the current values over `blocks` (tangent).
Eigen::MatrixXd jacobianOver(ceres::Problem& problem, const std::vector<double*>& blocks) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = blocks;
  ceres::CRSMatrix crs;
  REQUIRE(problem.Evaluate(options, nullptr, nullptr, nullptr, &crs));
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int k = crs.rows[r]; k < crs.rows[r + 1]; ++k) J(r, crs.cols[k]) = crs.values[k];
  return J;
}

void solve(ceres::Problem& problem) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  REQUIRE(summary.IsSolutionUsable());
}

}  // namespace

TEST_CASE("marginalising a linear-Gaussian problem gives the exact marginal", "[fusion][57.8]") {
  std::mt19937 gen(5);
  // x1 (3), x2 (2), x3 (3), x4 (2); x1 is connected to x2 and x3, x4 only to x3.
  std::array<Eigen::VectorXd, 4> x{Eigen::VectorXd::Random(3), Eigen::VectorXd::Random(2),
                                   Eigen::VectorXd::Random(3), Eigen::VectorXd::Random(2)};
  const std::array<int, 4> size{3, 2, 3, 2};
  const std::vector<std::vector<int>> factors{{0}, {0, 1}, {1, 2}, {0, 2}, {2, 3}, {3}, {1}};
  ceres::Problem problem;
  // The same factors stacked densely: A x = c over all 10 unknowns, offsets 0, 3, 5, 8.
  const std::array<int, 4> offset{0, 3, 5, 8};
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(0, 10);
  Eigen::VectorXd c(0);
  for (const auto& f : factors) {
    std::vector<Eigen::MatrixXd> Ai;
    std::vector<double*> blocks;
    const int rows = 3;
    Eigen::MatrixXd row_block = Eigen::MatrixXd::Zero(rows, 10);
    for (int b : f) {
      Ai.push_back(randomMatrix(rows, size[b], gen));
      row_block.middleCols(offset[b], size[b]) = Ai.back();
      blocks.push_back(x[b].data());
    }
    const Eigen::VectorXd ci = randomMatrix(rows, 1, gen);
    problem.AddResidualBlock(new LinearFactor(Ai, ci), nullptr, blocks);
    A.conservativeResize(A.rows() + rows, Eigen::NoChange);
    A.bottomRows(rows) = row_block;
    c.conservativeResize(c.size() + rows);
    c.tail(rows) = ci;
  }
  const Eigen::MatrixXd H = A.transpose() * A;
  const Eigen::VectorXd x_star = H.ldlt().solve(A.transpose() * c);
  // Marginal of (x2, x3, x4): its covariance is the full covariance's block.
  const Eigen::MatrixXd Sigma = H.inverse();
  const Eigen::MatrixXd marginal_information = Sigma.bottomRightCorner(7, 7).inverse();

  SECTION("the prior alone: information and mean of the blocks x1 connects to") {
    const auto prior = marginalPrior(problem, {x[0].data()});
    REQUIRE(prior);
    REQUIRE(prior->blocks().size() == 2);  // x2, x3
    // Lambda = H_kk - H_km H_mm^-1 H_mk over the factors touching x1 only.
    Eigen::MatrixXd A1 = Eigen::MatrixXd::Zero(0, 8);
    for (std::size_t k = 0; k < factors.size(); ++k) {
      if (std::find(factors[k].begin(), factors[k].end(), 0) == factors[k].end()) continue;
      A1.conservativeResize(A1.rows() + 3, Eigen::NoChange);
      A1.bottomRows(3) = A.block(3 * k, 0, 3, 8);
    }
    if (prior->blocks()[0].x == x[2].data()) {  // kept blocks in the order x3, x2: swap columns
      const Eigen::MatrixXd x2_columns = A1.middleCols(3, 2);
      A1.middleCols(3, 3) = Eigen::MatrixXd(A1.middleCols(5, 3));
      A1.middleCols(6, 2) = x2_columns;
    }
    const Eigen::MatrixXd H1 = A1.transpose() * A1;
    const Eigen::MatrixXd expected =
        H1.bottomRightCorner(5, 5) -
        H1.block(3, 0, 5, 3) * H1.topLeftCorner(3, 3).inverse() * H1.block(0, 3, 3, 5);
    CHECK((prior->information() - expected).norm() < 1e-9 * expected.norm());
  }

  SECTION("prior plus the remaining factors: the marginal information and mean of x2, x3, x4") {
    REQUIRE(marginalizeOut(problem, {x[0].data()}) != nullptr);
    CHECK(!problem.HasParameterBlock(x[0].data()));
    CHECK(problem.NumResidualBlocks() == 5);  // the prior, {x2,x3}, {x3,x4}, {x4}, {x2}
    const Eigen::MatrixXd J = jacobianOver(problem, {x[1].data(), x[2].data(), x[3].data()});
    const Eigen::MatrixXd information = J.transpose() * J;
    CHECK((information - marginal_information).norm() < 1e-9 * marginal_information.norm());
    solve(problem);
    Eigen::VectorXd x_kept(7);
    x_kept << x[1], x[2], x[3];
    CHECK((x_kept - x_star.tail(7)).norm() < 1e-9 * x_star.norm());
  }
}

namespace {

// Rotation prior on a quaternion (Ceres's w, x, y, z order): r = 2 vec(q_meas^-1 q) / sigma.
struct RotationPrior {
  Eigen::Vector4d q_meas;
  double sigma;
  template <typename T>
  bool operator()(const T* q, T* r) const {
    const T q_inv[4] = {T(q_meas[0]), T(-q_meas[1]), T(-q_meas[2]), T(-q_meas[3])};
    T e[4];
    ceres::QuaternionProduct(q_inv, q, e);
    for (int i = 0; i < 3; ++i) r[i] = T(2.0) * e[i + 1] / T(sigma);
    return true;
  }
};

// Position prior r = (p - a) / sigma.
struct PositionPrior {
  Eigen::Vector3d a;
  double sigma;
  template <typename T>
  bool operator()(const T* p, T* r) const {
    for (int i = 0; i < 3; ++i) r[i] = (p[i] - T(a[i])) / T(sigma);
    return true;
  }
};

// Relative position seen in the rotated frame: r = (R(q)^T (p2 - p1) - d) / sigma.
struct RelativePosition {
  Eigen::Vector3d d;
  double sigma;
  template <typename T>
  bool operator()(const T* q, const T* p1, const T* p2, T* r) const {
    const T q_inv[4] = {q[0], -q[1], -q[2], -q[3]};
    const T dp[3] = {p2[0] - p1[0], p2[1] - p1[1], p2[2] - p1[2]};
    T body[3];
    ceres::QuaternionRotatePoint(q_inv, dp, body);
    for (int i = 0; i < 3; ++i) r[i] = (body[i] - T(d[i])) / T(sigma);
    return true;
  }
};

// Consistent measurements of a true (q, p1, p2): the optimum is the truth with zero residuals, so
// the Gauss-Newton prior is exact to first order and the reduced solution's error is O(eps^2).
struct NonlinearProblem {
  const Eigen::Vector4d q_true = Eigen::Vector4d(0.9, 0.2, -0.3, 0.1).normalized();
  const Eigen::Vector3d p1_true{0.1, -0.2, 0.3}, p2_true{1.2, 0.4, 0.1};
  Eigen::Vector4d q{1.0, 0.0, 0.0, 0.0};
  Eigen::Vector3d p1 = Eigen::Vector3d::Zero(), p2 = Eigen::Vector3d::Zero();
  ceres::Problem problem;

  NonlinearProblem() {
    const Eigen::Quaterniond rotation(q_true[0], q_true[1], q_true[2], q_true[3]);
    const Eigen::Vector3d d = rotation.conjugate() * (p2_true - p1_true);
    problem.AddParameterBlock(q.data(), 4, new ceres::QuaternionManifold);
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<RotationPrior, 3, 4>(new RotationPrior{q_true, 0.1}),
        nullptr, q.data());
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<PositionPrior, 3, 3>(new PositionPrior{p1_true, 0.05}),
        nullptr, p1.data());
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RelativePosition, 3, 4, 3, 3>(
                                 new RelativePosition{d, 0.02}),
                             nullptr, q.data(), p1.data(), p2.data());
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RelativePosition, 3, 4, 3, 3>(
                                 new RelativePosition{d, 0.05}),
                             nullptr, q.data(), p1.data(), p2.data());
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<PositionPrior, 3, 3>(new PositionPrior{p2_true, 0.3}),
        nullptr, p2.data());
  }
};

}  // namespace

TEST_CASE("marginalising a nonlinear problem agrees with the full solution to first order",
          "[fusion][57.8]") {
  NonlinearProblem full;
  solve(full.problem);
  const Eigen::Vector4d q_star = full.q;
  const Eigen::Vector3d p2_star = full.p2;

  // Linearise at the optimum moved by eps, marginalise p1, solve the rest: the error from the
  // optimum must shrink at least like eps^2 (the prior is exact to first order).
  const auto errorAt = [&](double eps) {
    NonlinearProblem reduced;
    const ceres::QuaternionManifold manifold;
    const Eigen::Vector3d dq = eps * Eigen::Vector3d(0.7, -0.4, 0.5);
    manifold.Plus(q_star.data(), dq.data(), reduced.q.data());
    reduced.p1 = full.p1 + eps * Eigen::Vector3d(-0.3, 0.6, 0.2);
    reduced.p2 = p2_star + eps * Eigen::Vector3d(0.5, 0.1, -0.8);
    const ceres::ResidualBlockId id = marginalizeOut(reduced.problem, {reduced.p1.data()});
    REQUIRE(id != nullptr);
    CHECK(reduced.problem.NumResidualBlocks() == 3);  // rotation prior, p2 prior, the new prior
    solve(reduced.problem);
    Eigen::Vector3d dq_error;
    manifold.Minus(reduced.q.data(), q_star.data(), dq_error.data());
    return std::hypot(dq_error.norm(), (reduced.p2 - p2_star).norm());
  };
  const double e0 = errorAt(0.0), e1 = errorAt(1e-2), e2 = errorAt(1e-3);
  INFO("error at eps = 0: " << e0 << ", 1e-2: " << e1 << ", 1e-3: " << e2);
  CHECK(e0 < 1e-8);
  CHECK(e1 < 10.0 * 1e-2 * 1e-2);  // second order in eps
  CHECK(e2 < e1 / 50.0);
}

TEST_CASE("the prior's tangent Jacobian stays J0 away from its linearisation point",
          "[fusion][57.8]") {
  NonlinearProblem nl;
  const auto prior = marginalPrior(nl.problem, {nl.p1.data()});
  REQUIRE(prior);
  REQUIRE(prior->blocks().size() == 2);  // q (manifold), p2
  CHECK(prior->blocks()[0].manifold != nullptr);
  const std::vector<double*> blocks = prior->parameterBlocks();
  const ceres::ResidualBlockId id = nl.problem.AddResidualBlock(
      new LinearPrior(prior->blocks(), prior->J0(), prior->r0()), nullptr, blocks);
  // At x0 the residual is r0.
  Eigen::VectorXd r(prior->r0().size());
  double cost = 0.0;
  REQUIRE(nl.problem.EvaluateResidualBlock(id, false, &cost, r.data(), nullptr));
  CHECK((r - prior->r0()).norm() < 1e-12);
  // Move q and p2 and compare the tangent Jacobians Ceres hands the solver with J0.
  const ceres::QuaternionManifold manifold;
  const Eigen::Vector4d q_old = nl.q;
  const Eigen::Vector3d dq(0.05, -0.02, 0.03);
  manifold.Plus(q_old.data(), dq.data(), nl.q.data());
  nl.p2 += Eigen::Vector3d(0.1, 0.2, -0.1);
  Eigen::Matrix<double, -1, -1, Eigen::RowMajor> Jq(r.size(), 3), Jp(r.size(), 3);
  double* J[2] = {Jq.data(), Jp.data()};
  REQUIRE(nl.problem.EvaluateResidualBlock(id, false, &cost, r.data(), J));
  CHECK((Jq - prior->J0().leftCols(3)).norm() < 1e-12 * prior->J0().norm());
  CHECK((Jp - prior->J0().rightCols(3)).norm() < 1e-12 * prior->J0().norm());
  // and the residual is J0 (x (-) x0) + r0.
  Eigen::VectorXd dx(6);
  dx << dq, Eigen::Vector3d(0.1, 0.2, -0.1);
  CHECK((r - (prior->J0() * dx + prior->r0())).norm() < 1e-12);
}

TEST_CASE("marginalising a block that is not in the problem throws", "[fusion][57.8]") {
  NonlinearProblem nl;
  double stranger[3] = {0, 0, 0};
  CHECK_THROWS_WITH(marginalPrior(nl.problem, {stranger}), Catch::Contains("not in the problem"));
  CHECK_THROWS_AS(LinearPrior({}, Eigen::MatrixXd::Zero(2, 3), Eigen::VectorXd::Zero(2)),
                  std::invalid_argument);
}
