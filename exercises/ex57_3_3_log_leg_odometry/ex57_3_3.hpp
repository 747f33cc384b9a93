// Exercise 57.3.3: a leg odometry that reads a (simulated) log and is compared with the truth.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "io/log.hpp"
#include "model/quadruped.hpp"

namespace ex57_3_3 {

// World-frame base velocity from one log row: for every foot whose contact flag is set,
//   v_i = -R (w x r_i + J_i dq_i)
// with R the row's ground-truth attitude (gt_q; an attitude filter comes in 57.4/57.5), w the
// gyro reading, r_i = FK(q_i) and J_i the foot Jacobian of leg i; the answer is the mean of the
// v_i. Nothing when no foot is in contact (flight).
std::optional<Eigen::Vector3d> rowVelocity(const legkit::io::LogRow& row,
                                           const legkit::model::QuadrupedKinematics& kin);

// rowVelocity over a whole log against its ground-truth velocity gt_v.
struct Comparison {
  int rows_used = 0;             // rows with at least one foot in contact
  int rows_without_contact = 0;  // skipped rows
  double rmse = 0.0;             // sqrt(mean |v - gt_v|^2) over the rows used [m/s]
  double max_error = 0.0;        // max |v - gt_v| [m/s]
};
// Throws std::invalid_argument when the log lacks joints, contact flags or ground truth.
Comparison compareWithTruth(const legkit::io::Log& log,
                            const legkit::model::QuadrupedKinematics& kin);

// Reads the CSV at path (io/log_reader.hpp) and compares it with its truth.
Comparison compareLogFile(const std::string& path, const legkit::model::QuadrupedKinematics& kin);

}  // namespace ex57_3_3
