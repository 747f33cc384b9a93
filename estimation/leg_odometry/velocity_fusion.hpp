// Fusing the base velocities of several stance feet (section 57.3, multi-foot contact).
//
// Every stance foot i gives its own estimate v_i = -R (w_b x r_i + r_dot_i) (base_velocity.hpp).
// The chapter lists three ways to combine them:
//   simple mean          v = (1/k) sum_i v_i                         (flat, rigid ground)
//   force-weighted mean  v = sum_i w_i v_i, w_i = f_i / sum_j f_j    (soft ground: the loaded
//                                                                     feet slip least)
//   separate measurements, one 3-row measurement z_i = v_i of the state's v per foot, each with
//   its own covariance, which a Kalman filter stacks into one update; without a prior the
//   update reduces to the information-weighted mean fuseStacked() returns.
// Every contact must carry its body-frame foot velocity (ContactMeasurement::v_body).
#pragma once

#include <Eigen/Core>

#include "estimation/leg_odometry/base_velocity.hpp"
#include "estimation/leg_odometry/contact_span.hpp"

namespace legkit::leg_odometry {

// v = (1/k) sum_i v_i. Throws std::invalid_argument for an empty contact set (in flight the legs
// say nothing about v), a missing v_body, non-finite input or more than kMaxContacts contacts.
Eigen::Vector3d meanVelocity(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                             ContactSpan contacts);

// v = sum_i f_i v_i / sum_j f_j with normal_forces[i] the normal force on contacts[i] [N].
// Negative forces (sensor noise on an unloading foot) count as zero. Throws
// std::invalid_argument as meanVelocity does, when the sizes differ, or when no foot is loaded.
Eigen::Vector3d forceWeightedVelocity(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                                      ContactSpan contacts,
                                      const Eigen::Ref<const Eigen::VectorXd>& normal_forces);

// The stance feet as separate measurements of the world-frame base velocity v:
//   z = [v_1; ...; v_k],  h(v) = H_v v with H_v = [I; ...; I],  noise covariance Rn =
//   blockdiag(Cov(v_i)) from baseVelocityCovariance (with each contact's p_body covariance).
// Fixed capacity (kMaxContacts feet): building it does not allocate.
struct StackedVelocityMeasurement {
  static constexpr int kMaxRows = 3 * kMaxContacts;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxRows, 1>;
  using Jacobian = Eigen::Matrix<double, Eigen::Dynamic, 3, 0, kMaxRows, 3>;
  using Covariance = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxRows, kMaxRows>;

  Vector z;       // stacked foot-derived velocities v_i [m/s]
  Jacobian H_v;   // d h / d v
  Covariance Rn;  // measurement noise covariance

  int feet() const { return static_cast<int>(z.size() / 3); }
  // Innovation y = z - H_v v for a state velocity v (what a filter's update uses).
  Vector residual(const Eigen::Vector3d& v) const { return z - H_v * v; }
};

StackedVelocityMeasurement stackVelocityMeasurements(const Eigen::Matrix3d& R,
                                                     const Eigen::Vector3d& w_b,
                                                     ContactSpan contacts,
                                                     const FootVelocityNoise& noise);

// Velocity and covariance from the stacked measurements alone (generalised least squares):
//   P = (H^T Rn^-1 H)^-1 = (sum_i Cov(v_i)^-1)^-1,   v = P H^T Rn^-1 z.
// Throws std::invalid_argument when a foot's covariance is not positive definite.
struct FusedVelocity {
  Eigen::Vector3d v;
  Eigen::Matrix3d P;
};
FusedVelocity fuseStacked(const StackedVelocityMeasurement& m);

}  // namespace legkit::leg_odometry
