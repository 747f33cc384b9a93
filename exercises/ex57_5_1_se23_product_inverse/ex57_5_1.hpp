// Exercise 57.5.1: the SE_2(3) product and inverse, block by block.
#pragma once

#include <Eigen/Core>

namespace ex57_5_1 {

// An element of SE_2(3): attitude R (body to world), velocity v and position p in the world.
struct ExtendedPose {
  Eigen::Matrix3d R;
  Eigen::Vector3d v;
  Eigen::Vector3d p;
};

using Matrix5d = Eigen::Matrix<double, 5, 5>;

// The 5x5 matrix [[R, v, p], [0, 1, 0], [0, 0, 1]].
Matrix5d toMatrix(const ExtendedPose& X);

// X1 * X2, written out block by block (do not build and multiply 5x5 matrices).
ExtendedPose compose(const ExtendedPose& X1, const ExtendedPose& X2);

// X^-1, written out block by block.
ExtendedPose inverse(const ExtendedPose& X);

// True when M is in SE_2(3): its top-left block is a rotation (R^T R = I and det R = +1, both
// to within tol) and its last two rows are [0 0 0 1 0] and [0 0 0 0 1] (to within tol).
bool isInSE23(const Matrix5d& M, double tol);

}  // namespace ex57_5_1
