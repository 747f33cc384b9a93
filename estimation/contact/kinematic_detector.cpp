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
  if (!(p.ref_tau >= 0.0 && std::isfinite(p.ref_tau)))
    throw std::invalid_argument("kinematic: ref_tau must be >= 0 and finite");
  if (!(p.gravity >= 0.0 && std::isfinite(p.gravity)))
    throw std::invalid_argument("kinematic: gravity must be >= 0 and finite");
}

void KinematicDetector::reset() {
  has_ground_ = false;
  has_v_.fill(false);
  has_ref_ = false;
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

  std::array<double, kMaxFeet> z{};  // lowest point of each foot sphere, gravity-aligned [m]
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
    // c_i = -R (omega x B_p_f + B_v_f): the base velocity if foot i is still, low-passed
    const Eigen::Vector3d c = -(s.base.R * (s.gyro.cross(foot.p_body) + foot.v_body));
    const double alpha = params_.speed_tau > 0.0 ? s.dt / (params_.speed_tau + s.dt) : 1.0;
    v_bar_[i] = has_v_[i] ? (v_bar_[i] + alpha * (c - v_bar_[i])).eval() : c;
    has_v_[i] = true;
    z[i] = (s.base.R * foot.p_body).z() - params_.foot_radius;  // below the base
    z_low = std::min(z_low, z[i]);
  }
  if (!std::isfinite(z_low)) return out;  // no usable foot: z_ground unchanged
  if (!has_ground_) {
    h_ = s.base.p.z();       // the legs' own base height starts at the estimate's
    z_ground_ = h_ + z_low;  // and the ground at the first sample's lowest foot
    has_ground_ = true;
  }
  std::array<bool, kMaxFeet> near{};  // criterion 2: |z_f - z_ground| < h_thresh
  for (int i = 0; i < s.num_feet; ++i) {
    if (out.feet[i].problem != nullptr) continue;
    z[i] += h_;
    near[i] = std::abs(z[i] - z_ground_) < params_.h_thresh;
  }
  // v_ref predicted over this step with the IMU, R a_m + g (a sample's worth: no drift)
  if (has_ref_ && s.acc.allFinite())
    v_ref_ += (s.base.R * s.acc - Eigen::Vector3d(0.0, 0.0, params_.gravity)) * s.dt;
  // The stance feet share one c_i, the base velocity: among the feet at ground height, the largest
  // group that agrees within v_thresh of one of them (ties: the one nearest the predicted v_ref)
  // pulls v_ref toward its mean with time constant ref_tau.
  int anchor = -1, best_n = 0;
  double best_key = std::numeric_limits<double>::infinity();
  for (int k = 0; k < s.num_feet; ++k) {
    if (!near[k]) continue;
    int n = 0;
    for (int j = 0; j < s.num_feet; ++j)
      n += near[j] && (v_bar_[j] - v_bar_[k]).norm() < params_.v_thresh;
    const double key = has_ref_ ? (v_bar_[k] - v_ref_).norm() : z[k];
    // a lone foot (single support, or feet that all disagree) only continues v_ref
    if (n == 1 && has_ref_ && !(key < params_.v_thresh)) continue;
    if (n > best_n || (n == best_n && key < best_key)) {
      anchor = k;
      best_n = n;
      best_key = key;
    }
  }
  if (anchor >= 0) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int j = 0; j < s.num_feet; ++j) {
      if (near[j] && (v_bar_[j] - v_bar_[anchor]).norm() < params_.v_thresh) sum += v_bar_[j];
    }
    // smoothed; a group farther than v_thresh from v_ref replaces it (re-lock: no loop to lose)
    const Eigen::Vector3d mean = sum / best_n;
    const double alpha = params_.ref_tau > 0.0 ? s.dt / (params_.ref_tau + s.dt) : 1.0;
    v_ref_ = has_ref_ && (mean - v_ref_).norm() < params_.v_thresh
                 ? (v_ref_ + alpha * (mean - v_ref_)).eval()
                 : mean;
    has_ref_ = true;
  }

  double z_down_sum = 0.0, z_slow_low = std::numeric_limits<double>::infinity();
  int n_down = 0;
  for (int i = 0; i < s.num_feet; ++i) {
    FootContact& f = out.feet[i];
    if (f.problem != nullptr) continue;
    // criterion 1 against the legs' base velocity: |c_i - v_ref| < v_thresh
    const bool slow = has_ref_ && (v_bar_[i] - v_ref_).norm() < params_.v_thresh;
    f.contact = slow && near[i];
    f.probability = f.contact ? 1.0 : 0.0;
    if (f.contact) {
      z_down_sum += z[i];
      ++n_down;
    }
    if (slow) z_slow_low = std::min(z_slow_low, z[i]);
  }
  if (n_down > 0) {
    // z_ground moves toward the judged-down feet's mean, time constant ground_tau
    const double alpha = params_.ground_tau > 0.0 ? s.dt / (params_.ground_tau + s.dt) : 1.0;
    z_ground_ += alpha * (z_down_sum / n_down - z_ground_);
  } else if (std::isfinite(z_slow_low)) {
    z_ground_ = z_slow_low;  // re-anchor on the lowest stationary foot (judged from next sample)
  }
  // The legs' base height follows the stance feet's vertical velocity
  if (anchor >= 0) h_ += v_ref_.z() * s.dt;
  return out;
}

}  // namespace legkit::contact
