// From a log's robot-agnostic foot columns to the estimators' contact measurement.
//
// A log that carries body-frame foot positions (foot<k>_px.., with variances or a covariance)
// already holds everything a contact measurement needs, whatever the robot. Quadruped logs with
// only joint columns go through the kinematics instead (estimation/leg_odometry).
#pragma once

#include "io/log.hpp"
#include "model/contact_measurement.hpp"

namespace legkit::io {

// Foot `foot` of `row` as a ContactMeasurement (foot id, body-frame position, 3x3 covariance).
// Throws std::invalid_argument if the layout has no foot columns or `foot` is not one of its
// feet. Whether the foot is in contact is row.contact[foot] (when the layout has contact flags).
ContactMeasurement footMeasurement(const LogLayout& layout, const LogRow& row, int foot);

}  // namespace legkit::io
