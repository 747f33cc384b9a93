// The local ground plane through the stance footholds (section 57.7, terrain): z = a + b x + c y
// by least squares, A p = z with rows (1, x_i, y_i), p* = (A^T A)^-1 A^T z.
//
// Solved on centred points (the same minimiser, better conditioned): with the means
// (x_bar, y_bar, z_bar), (b, c) solves the 2x2 normal equations of the centred (x, y) scatter and
// a = z_bar - b x_bar - c y_bar. The plane is not determined (A^T A singular) when
//  - fewer than 3 feet stand (a trot's two-foot stance, a flight phase): kTooFewFeet;
//  - the (x, y) footholds lie on a line (a pace's same-side pair plus one more on that line):
//    kCollinear, when the smallest singular value of the centred (x, y) points divided by
//    sqrt(n) (the footholds' RMS spread across their best line) is below collinear_tol.
// The caller keeps the previous plane in those cases. Fixed-size, no allocation.
#pragma once

#include <Eigen/Core>

namespace legkit::slip {

struct GroundPlane {
  enum Status { kOk, kTooFewFeet, kCollinear };
  double a = 0.0, b = 0.0, c = 0.0;                   // z = a + b x + c y
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // (-b, -c, 1) / |(-b, -c, 1)|
  double slope = 0.0;                                 // angle to the horizontal [rad]
  double spread = 0.0;  // RMS spread of the footholds across their best line [m]
  double rms = 0.0;     // RMS of the fit's z residuals [m] (non-planar ground shows here)
  Status status = kTooFewFeet;

  // z of the plane at (x, y): the ground height under a point [m].
  double height(double x, double y) const { return a + b * x + c * y; }
};

// Fits the plane through feet_world[0..n) (world positions of the footholds). For status other
// than kOk the coefficients are the flat plane z = mean z (0 for n = 0). Throws
// std::invalid_argument for n < 0, a null pointer with n > 0 or a non-finite foothold.
GroundPlane fitGroundPlane(const Eigen::Vector3d* feet_world, int n, double collinear_tol = 0.02);

}  // namespace legkit::slip
