// Marginalisation for the fixed-lag smoother (section 57.8): the states that leave the window are
// removed from the Ceres problem and replaced by the Gaussian prior they leave on their neighbours.
//
// Linearising every residual block that touches the blocks m to remove, at the current values, in
// the tangent space of each block (Ceres applies the manifolds' PlusJacobian), gives the normal
// equations of the blocks m and of the blocks k they connect to:
//   [H_mm H_mk; H_km H_kk] dx = -[b_m; b_k],   H = J^T J,  b = J^T r.
// Eliminating dx_m (Schur complement) leaves the marginal information and gradient of k:
//   Lambda = H_kk - H_km H_mm^-1 H_mk,   g = b_k - H_km H_mm^-1 b_m,
// which LinearPrior holds as a square-root factor, Lambda = J0^T J0 and g = J0^T r0:
//   r(x) = J0 (x (-) x0) + r0,   0.5 |r|^2 = 0.5 dx^T Lambda dx + g^T dx + const,
// with (-) the block's manifold Minus (plain difference for a Euclidean block) and x0 the values
// at marginalisation. x0 and J0 never change afterwards (first-estimate Jacobians): the prior's
// tangent Jacobian stays J0 wherever the solver moves x, so that information the prior holds is
// never re-linearised and the window does not gain information it does not have. (The factors
// still in the window are re-linearised at every iteration; only the prior is frozen.)
// Blocks held constant are left out of the prior (they carry no tangent).
#pragma once

#include <ceres/cost_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace legkit::fusion {

class LinearPrior final : public ceres::CostFunction {
 public:
  struct Block {
    double* x = nullptr;                        // the parameter block the prior acts on
    const ceres::Manifold* manifold = nullptr;  // its manifold in the problem (none: Euclidean)
    std::vector<double> x0;                     // its linearisation point (ambient values)
    int tangent_size = 0;
  };

  // r = J0 (x (-) x0) + r0 over the concatenated tangents of `blocks`. Throws
  // std::invalid_argument when J0's columns are not the sum of the blocks' tangent sizes or its
  // rows differ from r0's.
  LinearPrior(std::vector<Block> blocks, Eigen::MatrixXd J0, Eigen::VectorXd r0);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const std::vector<Block>& blocks() const { return blocks_; }
  std::vector<double*> parameterBlocks() const;
  // Lambda = J0^T J0, the information of the blocks' tangent about x0.
  Eigen::MatrixXd information() const { return J0_.transpose() * J0_; }
  // g = J0^T r0, the gradient of the prior's cost at x0.
  Eigen::VectorXd gradient() const { return J0_.transpose() * r0_; }
  // The tangent offset from x0 of the prior's minimum, -Lambda^-1 g (the marginal mean).
  Eigen::VectorXd meanOffset() const;
  const Eigen::MatrixXd& J0() const { return J0_; }
  const Eigen::VectorXd& r0() const { return r0_; }

 private:
  std::vector<Block> blocks_;
  Eigen::MatrixXd J0_;
  Eigen::VectorXd r0_;
};

// Linearises the residual blocks of `problem` that touch any block of `marginalised` at the
// current values and eliminates those blocks: the prior on the (non-constant) blocks they connect
// to. `problem` is not changed. Null when nothing is connected (or Lambda is zero). Throws
// std::invalid_argument for a block that is not in the problem or a residual block that fails to
// evaluate, and std::runtime_error when H_mm is not positive definite (a marginalised block is
// unobserved). Eigenvalues of Lambda below `rank_tolerance` times the largest are dropped (J0 has
// fewer rows).
std::unique_ptr<LinearPrior> marginalPrior(ceres::Problem& problem,
                                           const std::vector<double*>& marginalised,
                                           double rank_tolerance = 1e-12);

// marginalPrior(), then removes the marginalised blocks (with their residual blocks) from
// `problem` and adds the prior to it (the problem owns it). Returns the prior's residual block,
// or null when nothing was connected.
ceres::ResidualBlockId marginalizeOut(ceres::Problem& problem,
                                      const std::vector<double*>& marginalised,
                                      double rank_tolerance = 1e-12);

}  // namespace legkit::fusion
