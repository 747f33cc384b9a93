// What the front end does to a recorded log before any estimator sees it (section 57.11: bringing
// a real robot): its time stamps and its joint velocities. A simulated log needs neither: its
// stamps are exact and its joint velocities are the simulator's.
//  - Time stamps. A robot's logger stamps each row when it writes it, not when the sensors were
//    read: on the iCub walking log the row interval jitters from 0.2 to 27 ms about its 10.1 ms
//    mean (standard deviation 25 % of the mean), while the angles differentiate cleanly only on
//    a regular clock (RMS 0.46 rad/s against the recorded 0.44 on the mean period, 2.8 rad/s on
//    the stamps). Smoothed stamps are the straight line fitted (least squares over the row
//    index) to the stamps of the rows within kStampWindow rows of each one: jitter averages out,
//    a slow drift of the rate stays, and a gap (a dropout) stays a gap.
//  - Joint velocities. A robot's recorded joint velocities may come from its own filter (the
//    iCub's lag and disagree with its angles); angles mean the backward difference of the angles
//    on the (smoothed) stamps, dq_k = (q_k - q_{k-1}) / (t_k - t_{k-1}), causal as on a robot, the
//    first row taking the second row's difference. A log with the angles only (no dq_ or
//    joint<k>_dq columns) always gets them: auto, the default, picks them for it.
//  - Held IMU samples (an IMU slower than the log) are counted, not changed: integrating a held
//    sample over each row is its zero-order hold, and the noise densities already give the
//    variance of an integral over any interval, however it is sampled.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "io/log.hpp"

namespace legkit {

enum class StampHandling { kLogged, kSmoothed, kAuto };
enum class JointVelocitySource { kLogged, kAngles, kAuto };

struct LogConditioning {
  // auto: smoothed when the stamps jitter by more than kStampJitterLimit, else as logged.
  StampHandling stamps = StampHandling::kAuto;
  // auto: as logged, or from the angles when the log has no velocity columns.
  JointVelocitySource joint_velocities = JointVelocitySource::kAuto;
};

// Stamps whose row intervals have a standard deviation above this fraction of their mean are
// jittery. A clocked log has none (every simulated log: 0); the iCub walking log has 0.25.
constexpr double kStampJitterLimit = 0.1;
// A row interval longer than this many median intervals is a gap (a dropout), not jitter: the
// jitter leaves it out and the smoothing does not reach across it. The iCub walking log's longest
// interval is 2.7 median ones (a late stamp followed by an early one).
constexpr double kStampGapFactor = 4.0;
// The half window of the smoothed stamps [rows]. On the iCub walking log (ESKF / InEKF position
// RMSE, angles differentiated): 0.026 / 0.025 m at 10 rows, 0.027 / 0.025 at 25, 0.028 / 0.026
// at 50 and on one line through the whole log; 10 rows is the shortest that averages a row's
// jitter down by sqrt(21).
constexpr int kStampWindow = 10;

// The standard deviation of the row intervals over their mean, gaps left out (0 for fewer than
// 3 rows).
double stampJitter(const std::vector<double>& t);
// Each stamp replaced by the straight line fitted to the stamps within `half_window` rows of it
// and not across a gap, evaluated at its row. Throws std::invalid_argument naming the row when
// the result would not increase strictly.
std::vector<double> smoothedStamps(const std::vector<double>& t, int half_window = kStampWindow);

// The time base of a recorded log, checked before anything else: at least two rows; a median
// period outside [10 us, 100 ms] means the stamps are not in seconds; a step longer than max_gap
// (default: 10 median periods) is a hole no estimator should bridge. Throws std::invalid_argument
// naming the file and line (and `gap_option`, the way to give another bound).
void checkTimeBase(const io::Log& log, std::optional<double> max_gap,
                   const std::string& gap_option);

// What condition() did, for the run's summary.
struct ConditioningReport {
  double jitter = 0.0;            // stampJitter() of the log as recorded
  bool stamps_smoothed = false;   // the stamps were replaced by smoothedStamps()
  double max_stamp_shift = 0.0;   // the largest |smoothed - logged| [s]
  std::string smoothing_failure;  // auto only: why the jittery stamps were kept as logged
  bool velocities_from_angles = false;
  bool velocities_absent = false;  // the log has angles without velocity columns
  int held_imu_rows = 0;           // rows whose gyro and accelerometer equal the row before
  std::string describe() const;    // one line
};

// Applies `what` to `log` (joint velocities of the quadruped's q and of generic joints alike).
// A log without joint columns keeps its velocities (there are none to replace). Throws
// std::invalid_argument naming frontend.joint_velocities when it is `logged` and the log has the
// angles without velocity columns.
ConditioningReport condition(io::Log& log, const LogConditioning& what);

}  // namespace legkit
