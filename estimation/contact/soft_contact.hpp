// The soft form of contact (section 57.6): instead of a hard stance/swing switch, the contact
// probability p_c scales how much a filter trusts a foot.
//  - measurement noise:  R_i = R_contact / (p_c + eps) + R_swing (1 - p_c)
//    p_c -> 1 gives R_contact (trust the leg); p_c -> 0 gives a huge R (ignore it);
//  - foot process noise: Q_f = [p_c sigma_contact^2 + (1 - p_c) sigma_swing^2] I dt
//    p_c -> 1 pins the foot; p_c -> 0 lets it wander as a swing foot's would.
// A foot at p_c = 0.6 is half trusted, which costs far less than a confident wrong flag.
#pragma once

#include <Eigen/Core>

namespace legkit::contact {

struct SoftContactParams {
  double eps = 0.01;          // keeps R finite at p_c = 0 (R_contact / 0.01: 100 times R_contact)
  double swing_sigma = 0.05;  // [m] position noise of a foot that is not on the ground (R_swing)
  // Feet below this p_c are not handed to the filters at all (their R would say "ignore" anyway).
  double min_probability = 0.05;
};

// R_i = R_contact / (p_c + eps) + R_swing (1 - p_c), with R_swing = swing_sigma^2 I.
inline Eigen::Matrix3d softMeasurementCov(const Eigen::Matrix3d& R_contact, double p_c,
                                          const SoftContactParams& s = {}) {
  return R_contact / (p_c + s.eps) +
         (s.swing_sigma * s.swing_sigma * (1.0 - p_c)) * Eigen::Matrix3d::Identity();
}

// Q_f / dt = p_c sigma_contact^2 + (1 - p_c) sigma_swing^2: the foot's random-walk density
// [m^2/s] for a contact probability p_c, between the stance and the swing densities.
inline double softFootNoiseDensity(double p_c, double sigma_contact, double sigma_swing) {
  return p_c * sigma_contact * sigma_contact + (1.0 - p_c) * sigma_swing * sigma_swing;
}

}  // namespace legkit::contact
