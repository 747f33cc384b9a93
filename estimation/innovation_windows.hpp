// The stance-foot NIS of a run (InnovationStats, estimator.hpp) over windows of consecutive
// samples (issue 22 item 3). A filter's per-sample NIS cannot judge its noise settings at 1 kHz:
// the front end's stance-foot covariance carries a white floor (foot_point_sigma, 5 mm) that stands
// for slow errors (the foot rolling and creeping) while the white part of a reading is encoder
// noise, ~0.05 mm; every sample's r^T S^-1 r is then ~0.002 (physics trot, every stance density
// from 1e-4 to 0.01: `legkit run` with --config). What the settings get wrong shows in how the
// innovations add up. For a consistent filter the innovations are white with covariance S_k, so
// the sum of a foot's innovations over a window, sum r_k, has covariance sum S_k and
//   NIS_w = (sum r_k)^T (sum S_k)^-1 (sum r_k)  ~  chi-square(3)
// (the time-averaged innovation test of Bar-Shalom, Li and Kirubarajan, sec. 5.4); innovations that
// keep one sign (a foot pinned harder than it is) make it grow with the window, white ones do not.
// A window is kWindow consecutive counted updates of one foot (p_c >= kNisMinProbability), closed
// early when the foot has none at a sample (lift-off, settling, a gated update) or at reset().
// Fixed size: no allocation.
#pragma once

#include <Eigen/Core>
#include <array>

#include "estimation/estimator.hpp"

namespace legkit {

class InnovationWindows {
 public:
  static constexpr int kWindow = 50;  // samples (50 ms at 1 kHz)
  static constexpr int kMaxFeet = 8;  // foot ids [0, 8), as the Estimator contract

  void reset() {
    count_.fill(0);
    used_.fill(false);
  }
  // One counted update of `foot`: its innovation r and innovation covariance S.
  void add(int foot, const Eigen::Vector3d& r, const Eigen::Matrix3d& S, InnovationStats& stats) {
    if (count_[foot] == 0) {
      sum_r_[foot].setZero();
      sum_S_[foot].setZero();
    }
    sum_r_[foot] += r;
    sum_S_[foot] += S;
    used_[foot] = true;
    if (++count_[foot] == kWindow) close(foot, stats);
  }
  // At the end of each step: the windows of the feet without a counted update at it are closed.
  void endStep(InnovationStats& stats) {
    for (int foot = 0; foot < kMaxFeet; ++foot) {
      if (!used_[foot] && count_[foot] > 0) close(foot, stats);
      used_[foot] = false;
    }
  }

 private:
  // NIS_w of foot's window into stats (a sum_S that does not factorise adds nothing); the window
  // restarts. (In innovation_windows.cpp: its LLT kept out of this widely included header.)
  void close(int foot, InnovationStats& stats);

  std::array<Eigen::Vector3d, kMaxFeet> sum_r_;
  std::array<Eigen::Matrix3d, kMaxFeet> sum_S_;
  std::array<int, kMaxFeet> count_{};
  std::array<bool, kMaxFeet> used_{};
};

}  // namespace legkit
