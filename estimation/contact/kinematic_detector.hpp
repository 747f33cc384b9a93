// Method 6 of section 57.6: contact from kinematics alone (joint encoders and the IMU, no force or
// torque). A foot on the ground neither moves nor leaves the ground's height, so foot i is in
// contact when BOTH
//   criterion 1 (speed):  |v_f,i| = |v + R (omega x B_p_f,i + B_v_f,i)| < v_thresh
//   criterion 2 (height): |z_f,i - z_ground| < h_thresh
// hold, with v, R the base estimate of the previous step (the chicken-and-egg rule), omega the
// gyro, B_p_f = FK(q), B_v_f = J(q) dq. Either alone misjudges: a swing foot at the top of its arc
// is slow, a foot skimming the ground is low.
//
// Two departures from the raw criterion, both measured on the 10 s physics trot (seed 13, the true
// base standing in for the previous estimate; tests/contact/detectors_physics_test.cpp prints the
// scores):
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
// z_f,i is the lowest point of the foot sphere, z of (p + R B_p_f,i) minus foot_radius: FK gives
// the sphere's centre.
//
// z_ground: at the first sample (or after reset), the lowest foot's z. Then it follows the feet
// the detector judges down: each sample it moves toward their mean z with time constant
// ground_tau, so that it follows the drift of the base estimate's height and a gentle slope.
// When no foot passes both criteria but some pass the speed criterion (every foot stepped down a
// step the height criterion rejects, or the estimate's height jumped), z_ground is re-anchored to
// the lowest of those stationary feet. Its limits (the chapter's): soft ground defeats the speed
// criterion, stairs and slopes the height criterion.
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
};

class KinematicDetector : public ContactDetector {
 public:
  // Throws std::invalid_argument unless v_thresh, h_thresh > 0, foot_radius >= 0, ground_tau >= 0
  // (0: z_ground is the judged-down feet's mean of each sample), speed_tau >= 0.
  explicit KinematicDetector(const KinematicParams& params = {});

  std::string name() const override { return "kinematic"; }
  void reset() override;
  // Per foot: contact = criterion 1 AND criterion 2, probability 0 or 1, force NaN. Problems:
  //   "no base estimate"       signals.base is not valid (every foot)
  //   "base not finite"        a NaN or infinite base R, v, p or gyro (every foot)
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
  double z_ground_ = 0.0;
  std::array<bool, kMaxFeet> has_v_{};             // the foot's filter has a sample
  std::array<Eigen::Vector3d, kMaxFeet> v_bar_{};  // low-passed world foot velocity [m/s]
};

}  // namespace legkit::contact
