#include "estimation/contact/kinematic_detector.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "estimation/contact/gait_clock.hpp"

namespace legkit::contact {

KinematicDetector::KinematicDetector(const KinematicParams& p) : params_(p) {
  if (!(p.v_thresh > 0.0 && std::isfinite(p.v_thresh)))
    throw std::invalid_argument("kinematic: v_thresh must be positive and finite");
  if (!(p.h_thresh > 0.0 && std::isfinite(p.h_thresh)))
    throw std::invalid_argument("kinematic: h_thresh must be positive and finite");
  if (!(p.foot_radius >= 0.0 && std::isfinite(p.foot_radius)))
    throw std::invalid_argument("kinematic: foot_radius must be >= 0 and finite");
  if (!(p.ground_tau >= 0.0 && std::isfinite(p.ground_tau)))
    throw std::invalid_argument("kinematic: ground_tau must be >= 0 and finite");
  if (!(p.speed_tau >= 0.0 && std::isfinite(p.speed_tau)))
    throw std::invalid_argument("kinematic: speed_tau must be >= 0 and finite");
}

void KinematicDetector::reset() {
  has_ground_ = false;
  has_v_.fill(false);
}

double KinematicDetector::groundHeight() const {
  return has_ground_ ? z_ground_ : std::numeric_limits<double>::quiet_NaN();
}

ContactEstimate KinematicDetector::update(const ContactSignals& s) {
  checkSignals(s, "kinematic");
  ContactEstimate out;
  out.t = s.t;
  out.num_feet = s.num_feet;
  const char* all = nullptr;
  if (!s.base.valid)
    all = "no base estimate";
  else if (!(s.base.R.allFinite() && s.base.v.allFinite() && s.base.p.allFinite() &&
             s.gyro.allFinite()))
    all = "base not finite";

  std::array<double, kMaxFeet> z{};   // lowest point of each foot sphere, world [m]
  std::array<bool, kMaxFeet> slow{};  // criterion 1
  double z_low = std::numeric_limits<double>::infinity();
  for (int i = 0; i < s.num_feet; ++i) {
    FootContact& f = out.feet[i];
    const FootSignals& foot = s.feet[i];
    if (all != nullptr)
      f.problem = all;
    else if (!foot.has_kinematics)
      f.problem = "no leg kinematics";
    else if (!(foot.p_body.allFinite() && foot.v_body.allFinite()))
      f.problem = "kinematics not finite";
    if (f.problem != nullptr) {
      has_v_[i] = false;
      continue;
    }
    // v_f = v + R (omega x B_p_f + B_v_f): criterion 1's foot velocity, world frame, low-passed
    const Eigen::Vector3d v_f = s.base.v + s.base.R * (s.gyro.cross(foot.p_body) + foot.v_body);
    const double alpha = params_.speed_tau > 0.0 ? s.dt / (params_.speed_tau + s.dt) : 1.0;
    v_bar_[i] = has_v_[i] ? (v_bar_[i] + alpha * (v_f - v_bar_[i])).eval() : v_f;
    has_v_[i] = true;
    slow[i] = v_bar_[i].norm() < params_.v_thresh;
    z[i] = (s.base.p + s.base.R * foot.p_body).z() - params_.foot_radius;
    z_low = std::min(z_low, z[i]);
  }
  if (!std::isfinite(z_low)) return out;  // no usable foot: z_ground unchanged
  if (!has_ground_) {
    z_ground_ = z_low;  // start from the first sample's lowest foot
    has_ground_ = true;
  }

  double z_down_sum = 0.0, z_slow_low = std::numeric_limits<double>::infinity();
  int n_down = 0;
  for (int i = 0; i < s.num_feet; ++i) {
    FootContact& f = out.feet[i];
    if (f.problem != nullptr) continue;
    // criterion 2: |z_f - z_ground| < h_thresh
    f.contact = slow[i] && std::abs(z[i] - z_ground_) < params_.h_thresh;
    f.probability = f.contact ? 1.0 : 0.0;
    if (f.contact) {
      z_down_sum += z[i];
      ++n_down;
    }
    if (slow[i]) z_slow_low = std::min(z_slow_low, z[i]);
  }
  if (n_down > 0) {
    // z_ground moves toward the judged-down feet's mean, time constant ground_tau
    const double alpha = params_.ground_tau > 0.0 ? s.dt / (params_.ground_tau + s.dt) : 1.0;
    z_ground_ += alpha * (z_down_sum / n_down - z_ground_);
  } else if (std::isfinite(z_slow_low)) {
    z_ground_ = z_slow_low;  // re-anchor on the lowest stationary foot (judged from next sample)
  }
  return out;
}

}  // namespace legkit::contact
