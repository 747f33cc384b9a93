#include "estimation/innovation_windows.hpp"

#include <Eigen/Cholesky>

namespace legkit {

void InnovationWindows::close(int foot, InnovationStats& stats) {
  const Eigen::LLT<Eigen::Matrix3d> llt(sum_S_[foot]);
  if (llt.info() == Eigen::Success) stats.add(llt.matrixL().solve(sum_r_[foot]).squaredNorm(), 3);
  count_[foot] = 0;
}

}  // namespace legkit
