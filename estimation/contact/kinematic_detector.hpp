// Method 6 of section 57.6: contact from kinematics alone (joint encoders and the IMU, no force or
// torque). A foot on the ground neither moves nor leaves the ground's height, so foot i is in
// contact when BOTH
//   criterion 1 (speed):  |v_f,i| = |v + R (omega x B_p_f,i + B_v_f,i)| < v_thresh
//   criterion 2 (height): |z_f,i - z_ground| < h_thresh
// hold, with R the base estimate's attitude, omega the gyro, B_p_f = FK(q), B_v_f = J(q) dq.
// Either alone misjudges: a swing foot at the top of its arc is slow, a foot skimming the ground is
// low.
//
// What v and z_ground are measured against: NOT the estimate's velocity and height. The chapter's
// chicken-and-egg rule (judge with the previous estimate) closes a loop that can be lost for good:
// once the estimate's velocity is v_thresh off, no foot looks still, no stance foot corrects the
// filter, and it integrates the IMU alone. The former detector, which read v and p from the
// estimate, did so on a real Go1 trot (`--contact kinematic`: leg odometry 15.07 m, ESKF 15.33 m
// over 13 m travelled, no warning), and in the kit on the linear KF of every physics gait (60 s
// physics-trot 335 m, physics-real 13.96 m: the estimate's vz jumps to -0.6 m/s at the gait's
// start, 1.36 s, and no foot is judged down again) and on a filter started 0.5 m/s off (F1 0,
// never recovers; tests/contact/detectors_physics_test.cpp, "in the loop"). Only R's roll and
// pitch, which gravity keeps observable, now come from the estimate:
//  - c_i = -R (omega x B_p_f,i + B_v_f,i) is the base velocity if foot i is still: every stance
//    foot gives the same c_i. v is the detector's own v_ref: each sample predicted with the IMU,
//    v_ref += (R a_m + g) dt, then pulled with time constant ref_tau toward the mean c_i of the
//    largest group of feet at ground height that agree within v_thresh of one of them (ties: the
//    group nearest the predicted v_ref: a trot's lifting pair agrees with itself as well as the
//    landing pair does, and only the IMU tells which one the base moves with). A group farther
//    than v_thresh from v_ref replaces it at once, so no error of v_ref outlives a stance. A lone
//    foot (a biped's single support) only continues v_ref (within v_thresh of the prediction): a
//    base turning on locked legs, whose feet all disagree, has no foot down. The accelerometer's
//    bias b enters as b ref_tau (0.1 m/s^2: 5 mm/s).
//  - heights are z of (R B_p_f,i) plus the detector's own base height h, v_ref's z integrated
//    while a group is found (the legs' vertical odometry), not the estimate's p_z.
//  ref_tau = 0.05 s: with ref_tau = 0 (v_ref the group's mean, the tie-break the previous mean)
//    v_ref followed a trot's lifting pair to the end of the height band, and the 30 s physics-real
//    ESKF was 0.250 m, F1 0.905; ref_tau 0.01 / 0.02 / 0.05 / 0.1 s gave ESKF 0.092 / 0.093 /
//    0.093 / 0.093 m, linear KF 0.446 / 0.422 / 0.379 / 0.353 m, physics-turn linear KF 0.589 /
//    0.563 / 0.519 / 0.502 m, the ESKF unchanged elsewhere: flat from 0.05 s, where the
//    accelerometer's bias costs little.
// Measured (`legkit run --contact kinematic`, default durations, seed 1, before -> after; position
// RMSE [m] of leg odometry / linear KF / ESKF): physics-real 0.204 / 13.96 / 0.095 -> 0.172 /
// 0.208 / 0.093; physics-trot 0.622 / 335 / 0.300 -> 0.547 / 0.672 / 0.299; physics-turn 0.311 /
// 8.44 / 0.109 -> 0.264 / 0.248 / 0.109; physics-walk 0.266 / 7.62 / 0.056 -> 0.195 / 0.077 /
// 0.057; the iCub log 0.041 / 0.041 / 0.034 -> 0.042 / 0.038 / 0.032. Every filter now gets the
// same flags. What it cannot see: a wrong roll or pitch tilts the heights (10 degrees: 6.6 cm
// between feet 0.38 m apart), and a flight phase, where no foot is down, is judged on the IMU's
// v_ref alone.
//
// Two departures from the raw criterion, both measured on the 10 s physics trot (seed 13, the true
// base standing in for the previous estimate, before v_ref: the figures of the former criterion;
// tests/contact/detectors_physics_test.cpp prints the scores, now F1 0.941, no chatter):
//  - the speed criterion reads v_f,i low-passed with time constant speed_tau = 5 ms: at 1 kHz one
//    sample of the gyro's white noise (0.004 rad/s/sqrt(Hz): 0.13 rad/s) times a foot's 0.35 m
//    lever arm is 0.04 m/s per axis, and the raw criterion toggles on it (40 000 spurious toggles
//    a minute at 0.1 m/s);
//  - v_thresh = 0.2 m/s, not 0.1: what criterion 1 sees is the sphere's CENTRE, which keeps moving
//    on the ground (rolling, |omega_calf| r, and the contact's compliance settling: the true
//    centre speed is above 0.1 m/s for a fifth of the stance samples, 0.2 m/s at the 95th
//    percentile). At 0.1 m/s (5 ms) F1 is 0.916 with 1644 spurious toggles a minute; at 0.2 m/s
//    F1 0.943, none, touchdown 22 ms late. A swing foot moves at ~2 m/s; the slow top of its arc
//    is the height criterion's to reject.
//
// z_f,i is the lowest point of the foot sphere, h + z of (R B_p_f,i) minus foot_radius: FK gives
// the sphere's centre. h starts at the estimate's p_z at the first sample (or after reset).
//
// z_ground: at the first sample (or after reset), the lowest foot's z. Then it follows the feet
// the detector judges down: each sample it moves toward their mean z with time constant
// ground_tau, so that it follows the drift of h and a gentle slope. When no foot passes both
// criteria but some pass the speed criterion (every foot stepped down a step the height criterion
// rejects), z_ground is re-anchored to the lowest of those stationary feet. Its limits (the
// chapter's): soft ground defeats the speed criterion, stairs and slopes the height criterion.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>

#include "estimation/contact/contact_detector.hpp"

namespace legkit::contact {

struct KinematicParams {
  double v_thresh = 0.2;       // [m/s] criterion 1 (see above for why not 0.1)
  double h_thresh = 0.03;      // [m] criterion 2
  double foot_radius = 0.022;  // [m] the foot sphere's (model::QuadrupedGeometry::foot_radius)
  double ground_tau = 0.1;     // [s] time constant of z_ground's tracking
  double speed_tau = 0.005;    // [s] low-pass of the foot velocity (0: the raw sample)
  double ref_tau = 0.05;       // [s] v_ref's pull toward the stance group (0: the group's mean)
  double gravity = 9.81;       // [m/s^2] along world -z, for v_ref's prediction
};

class KinematicDetector : public ContactDetector {
 public:
  // Throws std::invalid_argument unless v_thresh, h_thresh > 0, foot_radius >= 0, ground_tau >= 0
  // (0: z_ground is the judged-down feet's mean of each sample), speed_tau, ref_tau, gravity >= 0.
  explicit KinematicDetector(const KinematicParams& params = {});

  std::string name() const override { return "kinematic"; }
  void reset() override;
  // Per foot: contact = criterion 1 AND criterion 2, probability 0 or 1, force NaN. Problems:
  //   "no base estimate"       signals.base is not valid (every foot)
  //   "base not finite"        a NaN or infinite base R, v, p or gyro (every foot; v and p are
  //                            not read, but an estimate with a NaN in it is not trusted for R)
  // A NaN accelerometer sample skips v_ref's prediction (v_ref held).
  //   "no leg kinematics"      the foot's has_kinematics is false
  //   "kinematics not finite"  a NaN or infinite p_body or v_body
  // A sample whose feet all have problems leaves z_ground unchanged; a foot's problem restarts its
  // velocity filter (from its next usable sample).
  ContactEstimate update(const ContactSignals& signals) override;

  // The ground height the detector believes [m] (world z), NaN before the first usable sample.
  double groundHeight() const;
  const KinematicParams& params() const { return params_; }

 private:
  KinematicParams params_;
  bool has_ground_ = false;
  double z_ground_ = 0.0;               // in the frame of h_ [m]
  double h_ = 0.0;                      // the legs' base height: v_ref's z integrated [m]
  std::array<bool, kMaxFeet> has_v_{};  // the foot's filter has a sample
  std::array<Eigen::Vector3d, kMaxFeet> v_bar_{};  // low-passed c_i [m/s]
  bool has_ref_ = false;
  Eigen::Vector3d v_ref_ = Eigen::Vector3d::Zero();  // the legs' base velocity [m/s]
};

}  // namespace legkit::contact
