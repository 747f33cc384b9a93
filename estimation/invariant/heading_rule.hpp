// How much of the heading rule a foot update gets: alpha in [0, 1], the ESKF's, InEKF's and
// TSIF's K <- (I - alpha E) K (eskf.hpp, "Heading rule"). alpha = 1 is the whole rule (no foot
// corrects yaw or the gyro bias about the vertical), alpha = 0 the plain filter.
//
// Why the turn rate decides it. Legs that read the speed short by a fraction e (a rubber foot that
// deforms and rolls, links off the model, timing) tell a false yaw rate e omega_z while the robot
// turns at omega_z: the IMU's centripetal acceleration omega_z x v against the legs' (1 - e) v
// asks the filter to turn faster. Walking straight the same scale error is a speed error along v,
// which no heading explains, and feet that stay put tell the vertical gyro bias with no scale in
// it. So the feet may correct the heading while the robot does not turn, and lose that right in
// proportion to the turn rate:
//   alpha = min(1, |omega_bar_z| / turn_rate),
// omega_bar_z the bias-corrected yaw rate R_hat (w_m - b_g_hat) . e_z, low-passed over
// turn_time (first order). A foot that the slip detector accuses (StepInput::slip) tells a false
// turn whatever the robot does (a foot sliding sideways on ice while the robot walks straight):
// alpha is 1 while any foot is accused and for turn_time after.
//
// Why the heading too, and not the bias alone. Taking the heading out of every update and letting
// the feet correct only the vertical bias while the robot walks straight leaves in the heading the
// drift that the bias made before it was learned, although the feet see it through the bias's
// correlation with the heading: over 12 x 300 s (57.10) that gave the ESKF ANEES/dof 6.4 and 3.7
// deg of yaw, against 1.36 and 1.3 deg with the heading and the bias corrected together.
//
// Fixed size, no allocation; reset with the filter.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace legkit::invariant {

// omega_z of the file comment: the world z of R_hat (w_m - b_g_hat) [rad/s].
inline double yawRate(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_m,
                      const Eigen::Vector3d& b_g) {
  return R.row(2).dot(w_m - b_g);
}

class HeadingRule {
 public:
  // turn_rate [rad/s] (0: the whole rule, alpha always 1), turn_time > 0 [s].
  HeadingRule(double turn_rate, double turn_time) : turn_rate_(turn_rate), turn_time_(turn_time) {}

  // Forgets the turn and any slip. The filters call it from their constructors and reset(), so
  // the initial values below are never read before it.
  void reset() {
    omega_bar_z_ = 0.0;  // state, not a setting: replaced by the first sample's rate (add)
    since_slip_ = turn_time_;
    started_ = false;
  }

  // One IMU sample: omega_z the bias-corrected world yaw rate [rad/s] over dt [s]; slipping
  // whether any foot of this sample is accused of slipping.
  void add(double omega_z, double dt, bool slipping) {
    if (!started_) {
      omega_bar_z_ = omega_z;  // no history: the first sample is the mean
      started_ = true;
    } else {
      const double a = dt / (turn_time_ + dt);  // first-order low-pass, time constant turn_time
      omega_bar_z_ += a * (omega_z - omega_bar_z_);
    }
    since_slip_ = slipping ? 0.0 : since_slip_ + dt;
  }

  // alpha of the file comment: the share of the rule the next foot updates get.
  double alpha() const {
    if (turn_rate_ <= 0.0 || since_slip_ < turn_time_) return 1.0;
    return std::min(1.0, std::abs(omega_bar_z_) / turn_rate_);
  }
  double turnRate() const { return omega_bar_z_; }  // omega_bar_z [rad/s]

 private:
  double turn_rate_;  // FilterParams::heading_turn_rate (its comment gives the measurement)
  double turn_time_;  // FilterParams::heading_turn_time
  // State, not settings: no measurement stands behind these initialisers, because reset() (called
  // from every filter's constructor) overwrites each before it is read.
  double omega_bar_z_ = 0.0;  // the low-passed yaw rate [rad/s]; add() sets it from sample 1
  double since_slip_ = 0.0;   // time since the last accused foot [s]; reset(): turn_time, no hold
  bool started_ = false;      // whether a sample has come
};

}  // namespace legkit::invariant
