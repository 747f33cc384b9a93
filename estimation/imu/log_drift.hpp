// Dead-reckoning drift on a recorded or simulated log (section 57.1): integrate the log's IMU
// columns alone, from the ground-truth state of the first row, with a fixed bias estimate b_hat,
// and compare with the log's ground truth. Each row's reading is held until the next row.
#pragma once

#include <vector>

#include "estimation/imu/drift_study.hpp"
#include "io/log.hpp"
#include "model/imu_model.hpp"

namespace legkit::imu {

// One sample every report_every seconds (the first at the first row's time, t measured from it).
// Throws std::invalid_argument if the log has no ground truth, fewer than two rows, or a
// non-increasing time stamp, or if report_every <= 0.
std::vector<DriftSample> deadReckoningDriftOnLog(const io::Log& log, const model::ImuBias& b_hat,
                                                 double report_every);

}  // namespace legkit::imu
