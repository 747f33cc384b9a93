// Stationary initialisation (section 57.9): while the robot stands still, roll and pitch from the
// gravity direction, the gyro bias from the mean rate, and the filters' initial state and
// covariance from both.
//
// Still window. The IMU samples are summed in kBlocks blocks of duration / kBlocks each (count,
// mean and sum of squared deviations per axis, Welford); the last kBlocks blocks are the window.
// It is still when the standard deviation of the blocks' means is below gyro_std_max on every gyro
// axis and below accel_std_max on every accelerometer axis. The spread of block means, not of
// the samples: a sample's white noise grows with the rate (Go2 densities at 1 kHz: 0.13 rad/s and
// 1.3 m/s^2 per sample, above both thresholds while standing), a block mean's is density /
// sqrt(block length) whatever the rate (0.013 rad/s and 0.13 m/s^2 for 0.1 s blocks), while a gait
// or a push moves the means by far more. A gap longer than one block starts the search over.
//
// What the window gives (InitialState):
//  - roll and pitch from the mean specific force a = R^T (-g) + b_a + noise (world z up):
//    roll = atan2(a_y, a_z), pitch = atan2(-a_x, sqrt(a_y^2 + a_z^2)); yaw = 0 (nothing on a
//    stand observes it); v = p = 0 (the world origin is where the robot stood).
//  - b_g = the mean rate (the Earth's 7.3e-5 rad/s is left in it: below the MEMS noise).
//  - b_a = 0. On a level stand the accelerometer bias and the tilt are not separable: a
//    horizontal bias b reads exactly like a tilt of b / g, and the vertical one is hidden in |g|.
//    Only rotating the robot into several attitudes separates them. When b_a is known from
//    elsewhere (a calibration), result(b_a, sigma_b_a) subtracts it before the tilt is taken.
//  - sigma_tilt = sqrt(s_mean^2 + sigma_b_a^2) / |g|: the standard error of the mean horizontal
//    specific force (the window's own standard deviation over sqrt(N)) and the bias it cannot tell
//    from tilt (accel_bias_sigma, the filters' prior sigma_accel_bias, when b_a is not given).
// The search gives up after max_wait seconds without a still window (gaveUp()): the caller then
// starts the filter from the pose it would have used without this (the log's first pose).
// add() never allocates: the blocks are a fixed ring.
#pragma once

#include <Eigen/Core>
#include <array>

#include "estimation/estimator.hpp"
#include "model/imu_model.hpp"

namespace legkit::engineering {

struct StationaryInitParams {
  bool enabled = true;
  double duration = 2.0;       // [s] of standing still averaged (the chapter: 2-3 s)
  double gyro_std_max = 0.02;  // [rad/s] per axis: above it the robot is moving
  double accel_std_max = 0.3;  // [m/s^2] per axis
  double max_wait = 10.0;      // [s] without a still window: give up, start as the log does
  // [m/s^2] per axis, the accelerometer bias the stand cannot tell from tilt (the filters' prior
  // sigma_accel_bias): it enters sigma_tilt.
  double accel_bias_sigma = 0.02;
};

class StationaryInitialiser {
 public:
  static constexpr int kBlocks = 20;  // blocks of duration / kBlocks in the window

  // Throws std::invalid_argument naming the field for a non-positive duration, a negative
  // threshold, max_wait or accel_bias_sigma, or a gravity that is not finite and along -z.
  explicit StationaryInitialiser(const StationaryInitParams& params,
                                 Eigen::Vector3d gravity = model::gravity());

  // Feed one IMU sample; true once a still window of `duration` has been found (from then on the
  // result is frozen and further samples are ignored; also after gaveUp()). Samples must come in
  // time order; one at an earlier time throws std::invalid_argument.
  bool add(double t, const model::ImuReading& imu);
  bool ready() const { return ready_; }
  bool gaveUp() const { return gave_up_; }
  // Roll and pitch from gravity, yaw 0, v = p = 0, b_g = mean gyro, b_a = 0, sigma_tilt as the
  // file comment says; x.t is the time of the window's last sample. Throws std::logic_error when
  // not ready().
  InitialState result() const;
  // The same with a known accelerometer bias b_a (per-axis sigma sigma_b_a), subtracted from the
  // mean specific force before the tilt is taken, and returned in b_a.
  InitialState result(const Eigen::Vector3d& b_a, double sigma_b_a) const;
  // The window's per-axis standard deviations of the block means (gyro, accel) when ready().
  const Eigen::Vector3d& gyroStd() const { return std_w_; }
  const Eigen::Vector3d& accelStd() const { return std_a_; }
  void reset();

 private:
  // Count, mean and sum of squared deviations of (w, a), six axes.
  struct Moments {
    double n = 0.0;
    Eigen::Matrix<double, 6, 1> mean = Eigen::Matrix<double, 6, 1>::Zero();
    Eigen::Matrix<double, 6, 1> m2 = Eigen::Matrix<double, 6, 1>::Zero();
    void add(const Eigen::Matrix<double, 6, 1>& x);
    void merge(const Moments& other);  // the parallel-variance rule (Chan et al.)
  };
  void closeBlock();

  StationaryInitParams params_;
  Eigen::Vector3d gravity_;
  std::array<Moments, kBlocks> blocks_{};  // ring of the last complete blocks
  int complete_ = 0;                       // complete blocks in the ring (<= kBlocks)
  int next_ = 0;                           // ring slot the next complete block goes to
  Moments current_;                        // the block being filled
  double block_start_ = 0.0, last_t_ = 0.0, first_t_ = 0.0;
  bool started_ = false, ready_ = false, gave_up_ = false;
  Moments window_;  // the still window, once ready
  Eigen::Vector3d std_w_ = Eigen::Vector3d::Zero(), std_a_ = Eigen::Vector3d::Zero();
};

}  // namespace legkit::engineering
