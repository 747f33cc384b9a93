// The scalar functions of the rotation angle that every closed form in lie/ is built from.
//
// With x = theta^2 (theta = |phi|), define for m >= 1
//
//     G_m(x) = sum_{k>=0} (-x)^k / (2k+m)!
//
//   G_1 = sin(theta)/theta              G_2 = (1 - cos theta)/theta^2
//   G_3 = (theta - sin theta)/theta^3   G_4 = (theta^2/2 + cos theta - 1)/theta^4   ...
//
// Because [phi]^3 = -theta^2 [phi], any power series in [phi] collapses onto I, [phi], [phi]^2,
// and its two coefficients are G's: for example Exp(phi) = I + G_1 [phi] + G_2 [phi]^2.
// The G's obey  theta^2 G_{m+2} = 1/m! - G_m,  which gives every closed form from G_1 and G_2,
// and their derivatives are again G's:  (1/theta) dG_m/dtheta = m G_{m+2} - G_{m+1}.
//
// Accuracy. G_1 and G_2 are evaluated from sin and cos of the half angle, which never cancels
// (1 - cos theta = 2 sin^2(theta/2)); they only need a series where theta^2 underflows. For
// m >= 3 the closed form subtracts nearly equal numbers, and each step of the recurrence
// multiplies the relative error by about (m-1) m / theta^2. Measured against a long-double
// series, the closed forms stay within 4e-16 (relative) from theta = 1 for G_3, 1.5 for G_4 and
// 2.5 for G_5 and G_6; below those switch points the Taylor series is summed instead, with just
// enough terms (8, 9, 11) that the first omitted term is below 1e-17. tests/lie/series_test.cpp
// checks both sides of every switch against a long-double reference.
#pragma once

#include <cmath>

namespace lie {

namespace detail {

constexpr double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

// sum_{k=0}^{N-1} (-x)^k / (2k+m)!, evaluated by Horner's rule from the smallest term up.
template <int m, int N, typename Scalar>
Scalar gSeries(Scalar x) {
  Scalar sum(0);
  for (int k = N - 1; k >= 0; --k) {
    sum = Scalar(1) / Scalar(factorial(2 * k + m)) - x * sum;
  }
  return sum;
}

}  // namespace detail

// The angle-dependent coefficients of one rotation vector, computed once and shared by Exp,
// the Jacobians and the Gamma functions.
template <typename Scalar>
class AngleSeries {
 public:
  explicit AngleSeries(Scalar theta2) : x_(theta2) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    if (x_ < kTinyX) {  // theta < 1e-5: two terms of each series are exact to rounding
      g1_ = Scalar(1) - x_ / Scalar(6);
      g2_ = Scalar(0.5) - x_ / Scalar(24);
    } else {
      const Scalar theta = sqrt(x_);
      const Scalar s = sin(theta / 2), c = cos(theta / 2);
      g1_ = Scalar(2) * s * c / theta;  // sin(theta)/theta
      g2_ = Scalar(2) * s * s / x_;     // (1 - cos theta)/theta^2
    }
  }

  Scalar theta2() const { return x_; }

  // G_m for m = 1..6 (see the file comment).
  template <int m>
  Scalar G() const {
    static_assert(m >= 1 && m <= 6, "G_m is provided for m = 1..6");
    if constexpr (m == 1) {
      return g1_;
    } else if constexpr (m == 2) {
      return g2_;
    } else {
      // Switch point theta_m^2 and number of Taylor terms for G_m (see the file comment).
      constexpr double switchX = m == 3 ? 1.0 : m == 4 ? 2.25 : 6.25;
      constexpr int terms = m == 3 ? 8 : m == 4 ? 9 : 11;
      if (x_ < switchX) return detail::gSeries<m, terms>(x_);
      return (Scalar(1) / Scalar(detail::factorial(m - 2)) - G<m - 2>()) / x_;
    }
  }

  // H_m = (1/theta) dG_m/dtheta = m G_{m+2} - G_{m+1}; the derivative of a coefficient with
  // respect to phi is H_m * phi^T.
  template <int m>
  Scalar H() const {
    return Scalar(m) * G<m + 2>() - G<m + 1>();
  }

  // Coefficient D of the inverse left Jacobian  Jl^{-1} = I - [phi]/2 + D [phi]^2,
  // D = (1 - (theta/2) cot(theta/2)) / theta^2 = (G_3 - 2 G_4) / (2 G_2): no cancellation left.
  Scalar jlInvD() const { return (G<3>() - Scalar(2) * G<4>()) / (Scalar(2) * g2_); }

 private:
  static constexpr double kTinyX = 1e-10;
  Scalar x_;
  Scalar g1_;
  Scalar g2_;
};

}  // namespace lie
