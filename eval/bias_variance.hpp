// Splits a velocity error into a slow part (bias) and a fast part (variance), for the linear KF's
// noise sweep (exercise 57.4.2).
//
// A filter tuned to trust its model (small Q, large R) averages the measurements over a long
// time: its error is smooth but lags the truth. Tuned the other way it follows every measurement
// and its error is noisy. With e_k = v_hat_k - v_k, the slow part is the centred moving average
//   s_k = mean of e_j over the rows j with |t_j - t_k| <= window / 2
// and the fast part f_k = e_k - s_k. The summaries are
//   bias     = sqrt(mean_k |s_k|^2)    [m/s]
//   variance = mean_k |f_k|^2          [m^2/s^2]
// so that bias^2 + variance is (up to the small cross term) the mean square error.
#pragma once

#include "eval/trajectory.hpp"
#include "io/log.hpp"

namespace legkit::eval {

struct BiasVariance {
  double bias = 0.0;      // RMS of the slow part of the velocity error [m/s]
  double variance = 0.0;  // mean square of its fast part [m^2/s^2]
};

// Throws std::invalid_argument if the log has no ground truth, the sizes differ, or
// window <= 0.
BiasVariance velocityBiasVariance(const io::Log& truth, const Trajectory& estimate, double window);

}  // namespace legkit::eval
