// Exercise 57.2.2: why the accelerometer corrects roll and pitch but not yaw, and when a
// magnetometer can. Attitude is parametrised by Z-Y-X Euler angles rpy = (roll, pitch, yaw):
//   R(rpy) = Rz(yaw) Ry(pitch) Rx(roll),  R maps body to world.
#pragma once

#include <Eigen/Core>

namespace ex57_2_2 {

// R(rpy) = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Matrix3d rotationFromRpy(const Eigen::Vector3d& rpy);

// What a bias-free accelerometer at rest reads: the specific force R^T (0 - g), g = (0, 0, -9.81).
Eigen::Vector3d accelerometerAtRest(const Eigen::Vector3d& rpy);

// What a magnetometer reads for the world magnetic field m_world: R^T m_world.
Eigen::Vector3d magnetometer(const Eigen::Vector3d& rpy, const Eigen::Vector3d& m_world);

// 3x3 Jacobian of a body-frame measurement with respect to (roll, pitch, yaw), column j being
// the derivative with respect to rpy(j). `which` selects the measurement: 0 = accelerometer at
// rest, 1 = magnetometer with field m_world (ignored for 0).
Eigen::Matrix3d measurementJacobian(int which, const Eigen::Vector3d& rpy,
                                    const Eigen::Vector3d& m_world);

// Heading error [rad] made by a compass that reads the field m_world + disturbance (e.g. a steel
// beam nearby) but believes it is m_world: the angle between the horizontal parts of the two.
double headingErrorFromDisturbance(const Eigen::Vector3d& m_world,
                                   const Eigen::Vector3d& disturbance);

}  // namespace ex57_2_2
