// The pose file (section 57.8): exteroceptive poses (SLAM, lidar odometry, motion capture) as a
// second log next to the IMU log, with its own strict reader.
//
// Format: CSV, one pose per line, '#' comment lines allowed before the header only. The header is
// exactly these 31 names, in this order:
//   t, t_arrival                      stamp of the pose, and when it reached the estimator [s]
//   px, py, pz                        p_MB: base position in the map frame [m]
//   qw, qx, qy, qz                    R_MB (base to map) as a unit quaternion, |q| = 1 to 1e-6
//   c00, c01, c02, c03, c04, c05,     the 21 upper-triangle entries of the 6x6 covariance, row by
//   c11, c12, c13, c14, c15,          row, of the error (dtheta, dp) in the map frame:
//   c22, c23, c24, c25,                 R_meas = Exp(dtheta) R_true, p_meas = p_true + dp
//   c33, c34, c35,                    (indices 0-2: dtheta [rad^2], 3-5: dp [m^2]; the mixed
//   c44, c45,                         entries in [rad m]); it must be symmetric positive definite
//   c55                               (the lower triangle is the mirror).
//   valid                             1: use the pose; 0: the source flags it as unusable
// Numbers in decimal or exponent form (std::from_chars, a leading '+' allowed; no hex; inf and
// nan refused); spaces around fields are allowed; LF, CR LF or CR line ends; a UTF-8 byte-order
// mark is skipped.
//
// The reader (readPoseLog) refuses, with an io::LogError "file:line: column 'c': what was
// expected": a wrong header, a row with the wrong number of fields, a field that is not a finite
// number, t not strictly increasing, t_arrival < t, a quaternion whose norm is off by more than
// 1e-6 (it is normalised otherwise), a covariance that is not positive definite, a valid flag
// other than 0 or 1, a blank line inside the data, a file with no rows. It never returns part of a
// file. The writer (writePoseLog) refuses the same poses (an error naming the pose's index and
// field) and checks that every byte reached the file; each number is the shortest text that reads
// back as the same double (std::to_chars), so t, t_arrival, p and the covariance read back
// exactly and the attitude, through its quaternion (written with qw >= 0), to
// kPoseLogAttitudeRoundTrip per entry of R_MB.
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "estimation/fusion/pose_measurement.hpp"

namespace legkit::fusion {

// How far an attitude written and read back may move, per entry of R_MB: 4e-15, 18 units in the
// last place of 1. The text is exact; the rounding is that of R -> quaternion -> R (Eigen's
// conversions), about 6 ulp for a file read and written again and up to 9 ulp for an attitude
// that never went through a quaternion. Measured over 1.6e7 attitudes (uniform, within 1e-6 rad
// of identity, within 1e-4 rad of a half turn): worst 1.9e-15 on the first round trip, 1.3e-15
// on the next ones. (The bound was stated as 1e-15 before, which 1.1e-15 and more broke; a
// refinement step of the writer's quaternion does not lower it, the reader's R(q) dominates.)
constexpr double kPoseLogAttitudeRoundTrip = 4e-15;

// The 31 column names of the header, in order.
const std::vector<std::string>& poseLogColumns();

// Throws io::LogError (cannot open, or any problem listed above).
std::vector<PoseMeasurement> readPoseLog(const std::string& path);
// The same from a stream; source names it in messages.
std::vector<PoseMeasurement> readPoseLog(std::istream& in, const std::string& source);

// Throws io::LogError naming the path and the pose (line of the file it would be on) for a pose
// the reader would refuse, or when the file cannot be written completely.
// comments: '#' lines written before the header (free text: source, seed, options).
void writePoseLog(const std::string& path, const std::vector<PoseMeasurement>& poses,
                  const std::vector<std::string>& comments = {});
void writePoseLog(std::ostream& out, const std::vector<PoseMeasurement>& poses,
                  const std::vector<std::string>& comments = {},
                  const std::string& destination = "<stream>");

}  // namespace legkit::fusion
