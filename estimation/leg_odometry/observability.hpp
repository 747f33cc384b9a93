// Which state directions the leg-kinematic measurements see (section 57.3, observability).
//
// State (error coordinates), in this order:
//   x = (dp, dtheta, dv, dd_1, ..., dd_k)      dimension 9 + 3k,
// base position p, attitude R = Exp(dtheta) R_hat (world-frame, left perturbation), base velocity
// v, and the world positions d_i of the k stance feet. Rows, per stance foot i:
//   position  y_i = R^T (d_i - p):  [ -R^T,  R^T [d_i - p]_x,  0,    ..., R^T (at d_i), ... ]
//   velocity  u_i = R^T v (the body-frame velocity leg odometry gives, -(w_b x r_i + r_dot_i)):
//                                   [  0,    R^T [v]_x,        R^T,  0 ... ]
// and, optionally, the gravity direction the accelerometer senses at low acceleration:
//   up        g_b = R^T e_z:        [  0,    R^T [e_z]_x,      0,    0 ... ]
// The measurements depend only on relative geometry, so moving the whole scene (base and all
// footholds) rigidly changes none of them: with the legs alone the null space is 6-dimensional
// (3 translations, 3 rotations). Gravity pins roll and pitch; what is left is 4-dimensional:
//   translation c:  dp = c, dd_i = c                                   (3 directions)
//   yaw:            dtheta = e_z, dp = e_z x p, dv = e_z x v, dd_i = e_z x d_i   (1 direction)
// whatever the number of stance feet (stand: k = 4, trot: k = 2).
#pragma once

#include <Eigen/Core>

#include "estimation/leg_odometry/contact_span.hpp"

namespace legkit::leg_odometry {

constexpr int kMaxObservabilityRows = 6 * kMaxContacts + 3;
constexpr int kMaxObservabilityCols = 9 + 3 * kMaxContacts;

using ObservabilityJacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0,
                                            kMaxObservabilityRows, kMaxObservabilityCols>;
using StateDirections = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0,
                                      kMaxObservabilityCols, kMaxObservabilityCols>;

// The stacked Jacobian above at (p, R, v) with stance-foot world positions d (one per column,
// 1 <= k <= kMaxContacts). Throws std::invalid_argument for bad input.
ObservabilityJacobian legKinematicsJacobian(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                                            const Eigen::Vector3d& v,
                                            const Eigen::Ref<const Eigen::Matrix3Xd>& d,
                                            bool with_gravity);

// Null space of a stacked Jacobian: its dimension (columns - numerical rank, singular values
// below 1e-9 times the largest count as zero) and an orthonormal basis (one column each).
struct NullSpace {
  int dimension = 0;
  StateDirections basis;
};
NullSpace nullSpace(const ObservabilityJacobian& H);
int nullSpaceDimension(const ObservabilityJacobian& H);

// The chapter's four unobservable directions at (p, v, d), columns: x, y, z translation, yaw.
StateDirections unobservableDirections(const Eigen::Vector3d& p, const Eigen::Vector3d& v,
                                       const Eigen::Ref<const Eigen::Matrix3Xd>& d);

}  // namespace legkit::leg_odometry
