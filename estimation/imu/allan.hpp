// Section 57.10: the overlapping Allan deviation of a resting IMU and the kit's noise parameters
// read from it (chapters/57.10-allan-variance.md).
//
// For a rate signal y_k sampled every tau0 (a gyro axis in rad/s, an accelerometer axis in m/s^2)
// the phase x_i = tau0 sum_{k<i} (y_k - mean y) turns the overlapping Allan variance at tau = m
// tau0 into one pass over the record (NIST SP 1065, the phase form):
//   sigma^2(tau) = sum_{i=0}^{N-2m} (x_{i+2m} - 2 x_{i+m} + x_i)^2 / (2 tau^2 (N + 1 - 2m)),
// which is O(N) per tau. The lines of the log-log plot give the noise terms (IEEE Std 952):
//   white noise (slope -1/2):       sigma(tau) = N_w / sqrt(tau)     -> N_w = sigma(1 s) on the
//   line bias random walk (slope +1/2):  sigma(tau) = K sqrt(tau / 3)     -> K = sigma(3 s) on the
//   line bias instability (flat bottom): sigma_min = 0.664 B              -> B = sigma_min / 0.664
// N_w is the kit's *_noise_density and K its *_bias_random_walk (model/imu_noise.hpp).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "model/imu_noise.hpp"

namespace legkit::imu {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One point of an Allan deviation curve.
struct AllanPoint {
  int m = 0;              // averaging factor: samples per cluster
  double tau = 0.0;       // averaging time m tau0 [s]
  double adev = 0.0;      // overlapping Allan deviation sigma(tau) [unit of the signal]
  double clusters = 0.0;  // n = N / m: independent clusters in the record
  // The 1-sigma interval adev (1 -+ 1 / sqrt(n)), NIST SP 1065's simple rule (n >= 4: lo > 0).
  double lo = 0.0;
  double hi = 0.0;
};

// Averaging factors m = round(ratio^k), k = 0, 1, ..., each distinct, up to samples / 4 (the
// largest leaves at least four independent clusters): ratio 2 gives octaves 1, 2, 4, ...,
// ratio 10^0.1 about ten per decade. Throws std::invalid_argument unless ratio > 1.
std::vector<int> allanFactors(std::size_t samples, double ratio = 2.0);

// Overlapping Allan deviation of the rate samples y (taken every tau0 seconds) at the given
// averaging factors (each in 1 .. y.size() / 4). Throws std::invalid_argument otherwise.
std::vector<AllanPoint> allanDeviation(const Eigen::Ref<const Eigen::VectorXd>& y, double tau0,
                                       const std::vector<int>& factors);

// A straight line of the log-log plot with a fixed slope, fitted to the points of a curve whose
// local slope (least squares over tau/2 .. 2 tau) is within a tolerance of it.
struct SlopeLine {
  double slope = 0.0;     // -1/2 white noise, +1/2 bias random walk
  double tau_read = 1.0;  // where the line is read [s]
  double level = kNaN;  // sigma on the line at tau_read: sigma(tau) = level (tau / tau_read)^slope
  double tau_first = kNaN, tau_last = kNaN;  // tau range of the points used [s]
  int points = 0;                            // points used (0: no such region in the curve)
  // Relative standard error of level, bounded by the n-weighted mean of the used points'
  // 1 / sqrt(n) (the standard deviation of a weighted mean is at most the weighted mean of the
  // standard deviations, whatever their correlation).
  double relative_error = kNaN;
  bool found() const { return points > 0; }
};

// The line of the given slope read at tau_read, fitted in log-log by the mean of
// log(adev) - slope log(tau / tau_read) over the qualifying points, each weighted by its n.
SlopeLine fitSlopeLine(const std::vector<AllanPoint>& curve, double slope, double tau_read,
                       double slope_tolerance);

struct AllanOptions {
  double ratio = 2.0;  // of successive averaging factors: 2 octaves, 10^0.1 ten per decade
  double slope_tolerance = 0.15;  // a point belongs to a line when its local slope is this close
};

// The noise terms of one axis.
struct AxisNoise {
  std::vector<AllanPoint> curve;
  SlopeLine white;                 // slope -1/2 read at 1 s: level = N_w [unit / sqrt(Hz)]
  SlopeLine random_walk;           // slope +1/2 read at 3 s: level = K [unit / s / sqrt(Hz)]
  double bias_instability = kNaN;  // B = sigma_min / 0.664 [unit]; NaN if the curve has no minimum
  double tau_min = kNaN;           // where sigma is smallest [s] (NaN as above)
};

// A resting IMU's recording: six axes sampled every tau0 seconds.
struct ImuRecording {
  static constexpr int kAxes = 6;  // gyro x, y, z [rad/s], accelerometer x, y, z [m/s^2]
  static constexpr std::array<const char*, kAxes> kAxisNames = {"gyro_x", "gyro_y", "gyro_z",
                                                                "acc_x",  "acc_y",  "acc_z"};
  double tau0 = 0.0;           // sample period: the mean step of the timestamps [s]
  std::vector<double> values;  // kAxes per sample, sample after sample
  std::string source;          // the file it came from (messages)

  std::size_t samples() const { return values.size() / kAxes; }
  // Axis a (0..5) of every sample.
  Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<kAxes>> axis(int a) const {
    return {values.data() + a, static_cast<Eigen::Index>(samples())};
  }
};

struct AllanAnalysis {
  double tau0 = 0.0;
  std::size_t samples = 0;
  std::array<AxisNoise, ImuRecording::kAxes> axes;
  // The kit's noise parameters: per sensor the largest of its three axes (a filter that assumes
  // one density for all three should not understate any). NaN where an axis lacks the line.
  model::ImuNoise noise() const;
  // Why the record cannot be a resting IMU's: the first axis whose white noise or bias random walk
  // exceeds model::ImuNoiseLimits (the motion of a robot, read as noise); empty when none does.
  std::string moved() const;
};

// Every axis's curve, lines and bias instability. Throws std::invalid_argument when the record is
// too short for a curve (fewer than 8 samples).
AllanAnalysis analyseImu(const ImuRecording& recording, const AllanOptions& options = {});

// Largest step of the timestamps relative to their median step that still counts as uniform, and
// the smallest: outside 0.5 .. 1.5 median steps a sample is missing (a gap) or doubled.
constexpr double kMaxStepRatio = 1.5;
constexpr double kMinStepRatio = 0.5;

// Reads a recording, in one of two formats, told apart by the header (the first line that is not
// a '#' comment):
//  - the kit's log CSV (io::readLog, chapters/57.0): t, gyro_*, acc_* and whatever else it holds;
//    held whole in memory (about 2 kB per row: minutes, not hours);
//  - the plain CSV of a raw IMU recording, header exactly t,gx,gy,gz,ax,ay,az (rad/s, m/s^2),
//    streamed (48 bytes per row: hours at 1 kHz).
// The timestamps must increase strictly and every step must lie within kMinStepRatio ..
// kMaxStepRatio of the median step. Throws io::LogError naming the file, line and column.
ImuRecording readImuRecording(const std::string& path);

}  // namespace legkit::imu
