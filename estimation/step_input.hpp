// Everything an estimator is given at one IMU sample. Robot-agnostic: the legs arrive as
// contact measurements (foot id, body-frame position, covariance, optional body-frame velocity),
// never as one robot's joint angles. Fixed capacity: filling it never allocates.
#pragma once

#include <array>

#include "estimation/leg_odometry/contact_span.hpp"
#include "model/contact_measurement.hpp"
#include "model/imu_model.hpp"

namespace legkit {

struct StepInput {
  double t = 0.0;         // sample time [s]
  double dt = 0.0;        // time since the previous sample [s]; 0 at the first sample
  model::ImuReading imu;  // gyro and accelerometer, body frame
  std::array<ContactMeasurement, leg_odometry::kMaxContacts> contacts{};  // feet in stance
  int num_contacts = 0;
  std::array<double, leg_odometry::kMaxContacts> normal_force{};  // per contact, when known [N]
  bool has_force = false;
  // The slip detector accused a foot at this sample and its reaction (slip::SlipGuard) acted: the
  // filters hold their heading rule whole (invariant/heading_rule.hpp).
  bool slip = false;

  leg_odometry::ContactSpan stance() const {
    return {contacts.data(), static_cast<std::size_t>(num_contacts)};
  }
};

}  // namespace legkit
