#include "estimation/fusion/marginalization.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace legkit::fusion {

namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

int totalTangent(const std::vector<LinearPrior::Block>& blocks) {
  int n = 0;
  for (const auto& b : blocks) n += b.tangent_size;
  return n;
}

}  // namespace

LinearPrior::LinearPrior(std::vector<Block> blocks, Eigen::MatrixXd J0, Eigen::VectorXd r0)
    : blocks_(std::move(blocks)), J0_(std::move(J0)), r0_(std::move(r0)) {
  if (J0_.cols() != totalTangent(blocks_))
    throw std::invalid_argument("LinearPrior: J0 has " + std::to_string(J0_.cols()) +
                                " columns, the blocks' tangents " +
                                std::to_string(totalTangent(blocks_)));
  if (J0_.rows() != r0_.size())
    throw std::invalid_argument("LinearPrior: J0 has " + std::to_string(J0_.rows()) + " rows, r0 " +
                                std::to_string(r0_.size()));
  set_num_residuals(static_cast<int>(r0_.size()));
  for (const auto& b : blocks_) {
    if (b.x0.empty() || (b.manifold && b.manifold->AmbientSize() != static_cast<int>(b.x0.size())))
      throw std::invalid_argument("LinearPrior: a block's x0 does not match its manifold");
    mutable_parameter_block_sizes()->push_back(static_cast<int>(b.x0.size()));
  }
}

std::vector<double*> LinearPrior::parameterBlocks() const {
  std::vector<double*> x;
  x.reserve(blocks_.size());
  for (const auto& b : blocks_) x.push_back(b.x);
  return x;
}

Eigen::VectorXd LinearPrior::meanOffset() const {
  return information().ldlt().solve(-gradient());
}

bool LinearPrior::Evaluate(double const* const* parameters, double* residuals,
                           double** jacobians) const {
  // dx = x (-) x0, block by block in the tangent.
  Eigen::VectorXd dx(J0_.cols());
  int col = 0;
  for (std::size_t i = 0; i < blocks_.size(); ++i) {
    const Block& b = blocks_[i];
    if (b.manifold) {
      if (!b.manifold->Minus(parameters[i], b.x0.data(), dx.data() + col)) return false;
    } else {
      for (int k = 0; k < b.tangent_size; ++k) dx[col + k] = parameters[i][k] - b.x0[k];
    }
    col += b.tangent_size;
  }
  Eigen::Map<Eigen::VectorXd>(residuals, r0_.size()) = J0_ * dx + r0_;
  if (!jacobians) return true;
  // The tangent Jacobian is J0 (first-estimate); Ceres multiplies the ambient one by
  // PlusJacobian(x) = P, so hand it J0_block P^+ with P^+ = (P^T P)^-1 P^T: J0_block P^+ P =
  // J0_block.
  col = 0;
  for (std::size_t i = 0; i < blocks_.size(); ++i) {
    const Block& b = blocks_[i];
    const int ambient = static_cast<int>(b.x0.size());
    if (jacobians[i]) {
      Eigen::Map<RowMajorMatrix> J(jacobians[i], r0_.size(), ambient);
      const auto J0_block = J0_.middleCols(col, b.tangent_size);
      if (b.manifold) {
        RowMajorMatrix P(ambient, b.tangent_size);
        if (!b.manifold->PlusJacobian(parameters[i], P.data())) return false;
        const Eigen::MatrixXd PtP = P.transpose() * P;
        J = J0_block * PtP.ldlt().solve(P.transpose());
      } else {
        J = J0_block;
      }
    }
    col += b.tangent_size;
  }
  return true;
}

std::unique_ptr<LinearPrior> marginalPrior(ceres::Problem& problem,
                                           const std::vector<double*>& marginalised,
                                           double rank_tolerance) {
  // Columns: the marginalised blocks' tangents first (m of them), then the kept blocks'.
  std::vector<double*> columns_of;
  std::unordered_map<const double*, int> column;
  int m = 0;
  for (double* x : marginalised) {
    if (!problem.HasParameterBlock(x))
      throw std::invalid_argument("marginalPrior: a block to marginalise is not in the problem");
    if (column.count(x) || problem.IsParameterBlockConstant(x)) continue;
    column[x] = m;
    columns_of.push_back(x);
    m += problem.ParameterBlockTangentSize(x);
  }
  // The residual blocks touching them, each once, in the problem's order (not by address, so that
  // the kept blocks' order, and the prior, are reproducible).
  std::vector<ceres::ResidualBlockId> residuals;
  std::unordered_set<ceres::ResidualBlockId> seen;
  for (double* x : marginalised) {
    std::vector<ceres::ResidualBlockId> ids;
    problem.GetResidualBlocksForParameterBlock(x, &ids);
    for (const ceres::ResidualBlockId id : ids)
      if (seen.insert(id).second) residuals.push_back(id);
  }

  std::vector<LinearPrior::Block> kept;
  int n = m;
  std::vector<std::vector<double*>> blocks_of(residuals.size());
  for (std::size_t k = 0; k < residuals.size(); ++k) {
    problem.GetParameterBlocksForResidualBlock(residuals[k], &blocks_of[k]);
    for (double* x : blocks_of[k]) {
      if (column.count(x) || problem.IsParameterBlockConstant(x)) continue;
      const int size = problem.ParameterBlockSize(x);
      column[x] = n;
      kept.push_back({x, problem.GetManifold(x), std::vector<double>(x, x + size),
                      problem.ParameterBlockTangentSize(x)});
      n += kept.back().tangent_size;
    }
  }
  if (kept.empty()) return nullptr;

  // H = sum J^T J, b = sum J^T r over the linearised residual blocks, in the tangent spaces.
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  for (std::size_t k = 0; k < residuals.size(); ++k) {
    const auto& xs = blocks_of[k];
    const int rows = problem.GetCostFunctionForResidualBlock(residuals[k])->num_residuals();
    std::vector<RowMajorMatrix> J(xs.size());
    std::vector<double*> J_ptr(xs.size(), nullptr);
    for (std::size_t i = 0; i < xs.size(); ++i) {
      if (problem.IsParameterBlockConstant(xs[i])) continue;
      J[i].resize(rows, problem.ParameterBlockTangentSize(xs[i]));
      J_ptr[i] = J[i].data();
    }
    Eigen::VectorXd r(rows);
    double cost = 0.0;
    if (!problem.EvaluateResidualBlock(residuals[k], true, &cost, r.data(), J_ptr.data()))
      throw std::invalid_argument("marginalPrior: a residual block failed to evaluate");
    for (std::size_t i = 0; i < xs.size(); ++i) {
      if (!J_ptr[i]) continue;
      const int ci = column.at(xs[i]);
      b.segment(ci, J[i].cols()) += J[i].transpose() * r;
      for (std::size_t j = 0; j < xs.size(); ++j) {
        if (!J_ptr[j]) continue;
        H.block(ci, column.at(xs[j]), J[i].cols(), J[j].cols()) += J[i].transpose() * J[j];
      }
    }
  }

  // Schur complement onto the kept blocks.
  const int nk = n - m;
  Eigen::MatrixXd Lambda = H.bottomRightCorner(nk, nk);
  Eigen::VectorXd g = b.tail(nk);
  if (m > 0) {
    const Eigen::LLT<Eigen::MatrixXd> Hmm(H.topLeftCorner(m, m));
    if (Hmm.info() != Eigen::Success)
      throw std::runtime_error("marginalPrior: H_mm is not positive definite (unobserved block)");
    const Eigen::MatrixXd Hmm_inv_Hmk = Hmm.solve(H.topRightCorner(m, nk));
    Lambda -= H.bottomLeftCorner(nk, m) * Hmm_inv_Hmk;
    g -= Hmm_inv_Hmk.transpose() * b.head(m);
  }
  Lambda = 0.5 * (Lambda + Lambda.transpose()).eval();

  // Lambda = U S U^T: J0 = S^1/2 U^T, r0 = S^-1/2 U^T g (rows of negligible eigenvalues dropped).
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Lambda);
  const Eigen::VectorXd& s = eig.eigenvalues();
  const double threshold = rank_tolerance * std::max(s.maxCoeff(), 0.0);
  int rank = 0;
  for (int i = 0; i < nk; ++i) rank += s[i] > threshold ? 1 : 0;
  if (rank == 0) return nullptr;
  Eigen::MatrixXd J0(rank, nk);
  Eigen::VectorXd r0(rank);
  for (int i = nk - rank, row = 0; i < nk; ++i, ++row) {
    const double sqrt_s = std::sqrt(s[i]);
    J0.row(row) = sqrt_s * eig.eigenvectors().col(i).transpose();
    r0[row] = eig.eigenvectors().col(i).dot(g) / sqrt_s;
  }
  return std::make_unique<LinearPrior>(std::move(kept), std::move(J0), std::move(r0));
}

ceres::ResidualBlockId marginalizeOut(ceres::Problem& problem,
                                      const std::vector<double*>& marginalised,
                                      double rank_tolerance) {
  std::unique_ptr<LinearPrior> prior = marginalPrior(problem, marginalised, rank_tolerance);
  for (double* x : marginalised)
    if (problem.HasParameterBlock(x)) problem.RemoveParameterBlock(x);
  if (!prior) return nullptr;
  const std::vector<double*> blocks = prior->parameterBlocks();
  return problem.AddResidualBlock(prior.release(), nullptr, blocks);
}

}  // namespace legkit::fusion
