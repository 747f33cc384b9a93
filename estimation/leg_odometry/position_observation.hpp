// Position observations from stance feet (section 57.3): a foot that stays put anchors the base.
//
// The foot point in the world is d_i = p + R r_i (r_i its body-frame position from kinematics).
// Hence, while foot i is in stance,
//   base position        p = d_i - R r_i           (d_i recorded at touchdown),
//   foot height          (p + R r_i)_z - rho       (contact point of a foot sphere of radius rho;
//                                                  equals the ground height under the foot),
// and a filter that carries p, R and d_i in its state uses the measurement
//   y_i = R^T (d_i - p)  (= r_i, what the encoders give),
// with the attitude perturbed on the left, R = Exp(dtheta) R_hat (world-frame error), so that
//   dy/dp = -R^T,   dy/ddtheta = R^T [d_i - p]_x,   dy/dd_i = R^T.
#pragma once

#include <Eigen/Core>

namespace legkit::leg_odometry {

// p = d - R r: base position from a stance foot at the world point d.
Eigen::Vector3d basePositionFromFoot(const Eigen::Vector3d& d, const Eigen::Matrix3d& R,
                                     const Eigen::Vector3d& r);

// d = p + R r: world position of the foot point (record it at touchdown).
Eigen::Vector3d footWorldPosition(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                                  const Eigen::Vector3d& r);

// (p + R r)_z - rho: height of the foot sphere's lowest point, i.e. of the ground under a stance
// foot (rho = foot radius, 0 when r already is the contact point).
double footContactHeight(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                         const Eigen::Vector3d& r, double foot_radius);

// p_z = h + rho - (R r)_z: base height over known flat ground at height h.
double baseHeightFromFoot(double ground_height, const Eigen::Matrix3d& R, const Eigen::Vector3d& r,
                          double foot_radius);

// The filter's foot measurement y = R^T (d - p) and, when asked for, its Jacobians (above).
Eigen::Vector3d footMeasurement(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                                const Eigen::Vector3d& d, Eigen::Matrix3d* J_y_p = nullptr,
                                Eigen::Matrix3d* J_y_theta = nullptr,
                                Eigen::Matrix3d* J_y_d = nullptr);

}  // namespace legkit::leg_odometry
