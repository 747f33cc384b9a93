// A scalar function of time carried with its first two time derivatives, so that every
// trajectory of the simulator is written once and its velocity and acceleration follow exactly
// (no finite differences anywhere in the ground truth).
#pragma once

#include <cmath>

namespace legkit::sim {

struct Jet {
  double f = 0.0;   // value
  double d = 0.0;   // first derivative
  double dd = 0.0;  // second derivative

  static Jet constant(double c) { return {c, 0.0, 0.0}; }
  static Jet time(double t) { return {t, 1.0, 0.0}; }
};

inline Jet operator+(const Jet& a, const Jet& b) {
  return {a.f + b.f, a.d + b.d, a.dd + b.dd};
}
inline Jet operator*(double c, const Jet& a) {
  return {c * a.f, c * a.d, c * a.dd};
}
// Product rule: (ab)'' = a'' b + 2 a' b' + a b''.
inline Jet operator*(const Jet& a, const Jet& b) {
  return {a.f * b.f, a.d * b.f + a.f * b.d, a.dd * b.f + 2.0 * a.d * b.d + a.f * b.dd};
}
// Chain rule: sin(a)'' = cos(a) a'' - sin(a) a'^2.
inline Jet sin(const Jet& a) {
  const double s = std::sin(a.f), c = std::cos(a.f);
  return {s, c * a.d, c * a.dd - s * a.d * a.d};
}

// Quintic Hermite segment on [0, T], evaluated at time u: starts at (p0, v0, a0) and ends at
// (p1, v1, a1) (value, rate, acceleration). u must lie in [0, T].
inline Jet quinticHermite(double p0, double v0, double a0, double p1, double v1, double a1,
                          double T, double u) {
  const double s = u / T;
  const double s2 = s * s, s3 = s2 * s, s4 = s3 * s, s5 = s4 * s;
  // Basis functions and their first and second derivatives with respect to s.
  const double h0 = 1 - 10 * s3 + 15 * s4 - 6 * s5, h0d = -30 * s2 + 60 * s3 - 30 * s4,
               h0dd = -60 * s + 180 * s2 - 120 * s3;
  const double h1 = s - 6 * s3 + 8 * s4 - 3 * s5, h1d = 1 - 18 * s2 + 32 * s3 - 15 * s4,
               h1dd = -36 * s + 96 * s2 - 60 * s3;
  const double h2 = 0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5,
               h2d = s - 4.5 * s2 + 6 * s3 - 2.5 * s4, h2dd = 1 - 9 * s + 18 * s2 - 10 * s3;
  const double h3 = 0.5 * s3 - s4 + 0.5 * s5, h3d = 1.5 * s2 - 4 * s3 + 2.5 * s4,
               h3dd = 3 * s - 12 * s2 + 10 * s3;
  const double h4 = -4 * s3 + 7 * s4 - 3 * s5, h4d = -12 * s2 + 28 * s3 - 15 * s4,
               h4dd = -24 * s + 84 * s2 - 60 * s3;
  const double h5 = 10 * s3 - 15 * s4 + 6 * s5, h5d = 30 * s2 - 60 * s3 + 30 * s4,
               h5dd = 60 * s - 180 * s2 + 120 * s3;
  const double T2 = T * T;
  const auto combine = [&](double b0, double b1, double b2, double b3, double b4, double b5) {
    return p0 * b0 + v0 * T * b1 + a0 * T2 * b2 + a1 * T2 * b3 + v1 * T * b4 + p1 * b5;
  };
  return {combine(h0, h1, h2, h3, h4, h5), combine(h0d, h1d, h2d, h3d, h4d, h5d) / T,
          combine(h0dd, h1dd, h2dd, h3dd, h4dd, h5dd) / T2};
}

// Smooth start from 0 to 1 over [t0, t0 + T]: the septic smoothstep 35x^4 - 84x^5 + 70x^6 - 20x^7
// (x = (t - t0) / T), whose first three derivatives vanish at both ends, so a ramped motion keeps
// a continuous jerk.
inline Jet smoothStep(double t0, double T, double t) {
  if (t <= t0) return Jet::constant(0.0);
  if (t >= t0 + T) return Jet::constant(1.0);
  const double x = (t - t0) / T;
  const double x2 = x * x, x3 = x2 * x, x4 = x3 * x;
  return {x4 * (35.0 - 84.0 * x + 70.0 * x2 - 20.0 * x3),
          x3 * (140.0 - 420.0 * x + 420.0 * x2 - 140.0 * x3) / T,
          x2 * (420.0 - 1680.0 * x + 2100.0 * x2 - 840.0 * x3) / (T * T)};
}

// Integral of smoothStep from t0 to t: the distance covered by a speed that ramps up smoothly.
inline Jet smoothStepIntegral(double t0, double T, double t) {
  if (t <= t0) return Jet::constant(0.0);
  if (t >= t0 + T) return {0.5 * T + (t - t0 - T), 1.0, 0.0};
  const Jet s = smoothStep(t0, T, t);
  const double x = (t - t0) / T;
  const double x2 = x * x, x3 = x2 * x, x5 = x2 * x3;
  return {T * x5 * (7.0 - 14.0 * x + 10.0 * x2 - 2.5 * x3), s.f, s.d};
}

}  // namespace legkit::sim
