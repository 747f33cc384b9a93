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
// Accuracy. G_1 and G_2 come from sin(theta/2)/(theta/2) and cos(theta/2), which never cancel
// (1 - cos theta = 2 sin^2(theta/2)). For theta < pi these come from sin(q)/q and cos(q) of the
// quarter angle q = theta/4, summed as Taylor series in q^2 <= pi^2/16 with 9 terms each (the
// first omitted one is below 1e-17 of the sum): no square root, no sin or cos, no division.
// Beyond pi they come from std::sin and std::cos of the half angle. For m >= 3 the closed form
// subtracts nearly equal numbers, and each step of the recurrence multiplies the relative error by
// about (m-1) m / theta^2. Measured against a long-double series, the closed forms stay within
// 4e-16 (relative) from theta = 1 for G_3, 1.5 for G_4 and 2.5 for G_5 and G_6; below those switch
// points the Taylor series is summed instead, with just enough terms (8, 9, 11) that the first
// omitted term is below 1e-17. tests/lie/series_test.cpp checks both sides of every switch against
// a long-double reference.
#pragma once

#include <array>
#include <cmath>

namespace lie {

namespace detail {

// T in a parameter list without deducing it from that argument (std::type_identity of C++20).
template <typename T>
struct TypeIdentity {
  using type = T;
};
template <typename T>
using NonDeduced = typename TypeIdentity<T>::type;

constexpr long double factorial(int n) {
  return n <= 1 ? 1.0L : n * factorial(n - 1);
}

// Taylor coefficients c_k = 1/(2k+m)! of G_m, and d_k = (2k+2)/(2k+5)! of G_4 - 3 G_5, as
// compile-time tables (long double, so that a long-double AngleSeries keeps its precision).
template <int m, int N>
constexpr std::array<long double, N> gCoefficients() {
  std::array<long double, N> c{};
  for (int k = 0; k < N; ++k) c[k] = 1.0L / factorial(2 * k + m);
  return c;
}
template <int N>
constexpr std::array<long double, N> g45Coefficients() {
  std::array<long double, N> c{};
  for (int k = 0; k < N; ++k) c[k] = (2.0L * k + 2.0L) / factorial(2 * k + 5);
  return c;
}

// sum_{k=0}^{N-1} (-x)^k c_k by Horner's rule, from the smallest term up.
template <typename Scalar, std::size_t N>
Scalar alternatingSeries(Scalar x, const std::array<long double, N>& c) {
  Scalar sum(c[N - 1]);
  for (int k = static_cast<int>(N) - 2; k >= 0; --k) sum = Scalar(c[k]) - x * sum;
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
    if (x_ < kHalfAngleSeriesX) {
      // With q = theta/4: sin(q)/q and cos(q), summed in q^2 = x/16 (see the file comment), then
      // doubled to the half angle h = 2q: sin(h)/h = sinc(q) cos(q), cos h = 1 - 2 q^2 sinc(q)^2.
      static constexpr auto sincCoefficients = detail::gCoefficients<1, 9>();  // 1/(2k+1)!
      static constexpr auto cosCoefficients = detail::gCoefficients<0, 9>();   // 1/(2k)!
      const Scalar q2 = x_ / Scalar(16);
      const Scalar sincQ = detail::alternatingSeries(q2, sincCoefficients);
      const Scalar sincH = sincQ * detail::alternatingSeries(q2, cosCoefficients);
      const Scalar cosH = Scalar(1) - x_ / Scalar(8) * sincQ * sincQ;
      g1_ = sincH * cosH;               // sin(2h)/2h = sinc(h) cos h
      g2_ = sincH * sincH / Scalar(2);  // (1 - cos 2h)/4h^2 = 2 sin^2(h)/4h^2
    } else {
      const Scalar theta = sqrt(x_), s = sin(theta / Scalar(2)), c = cos(theta / Scalar(2));
      g1_ = Scalar(2) * s * c / theta;  // sin(theta)/theta
      g2_ = Scalar(2) * s * s / x_;     // (1 - cos theta)/theta^2
    }
  }

  // From theta with its sine and cosine, which SO3::logOfMatrix has: two divisions instead of
  // the series (1 - cos theta = sin^2 theta/(1 + cos theta) where cos theta > 0: no cancellation).
  AngleSeries(Scalar theta, Scalar sinTheta, Scalar cosTheta) : x_(theta * theta) {
    if (x_ < kTinyX) {  // theta < 1e-5: two terms of each series are exact to rounding
      g1_ = Scalar(1) - x_ / Scalar(6);
      g2_ = Scalar(0.5) - x_ / Scalar(24);
    } else {
      const Scalar oneMinusCos = cosTheta > Scalar(0)
                                     ? Scalar(sinTheta * sinTheta / (Scalar(1) + cosTheta))
                                     : Scalar(Scalar(1) - cosTheta);
      g1_ = sinTheta / theta;
      g2_ = oneMinusCos / x_;
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
      static constexpr auto coefficients = detail::gCoefficients<m, terms>();
      if (x_ < switchX) return detail::alternatingSeries(x_, coefficients);
      // 1/(m-2)! as a Scalar of its own: with Eigen::AutoDiffScalar<VectorXd> an expression of
      // two constants (empty derivative vectors) cannot be resized to meet a variable.
      const Scalar inverseFactorial = Scalar(1) / Scalar(detail::factorial(m - 2));
      return (inverseFactorial - G<m - 2>()) / x_;
    }
  }

  // H_m = (1/theta) dG_m/dtheta = m G_{m+2} - G_{m+1}; the derivative of a coefficient with
  // respect to phi is H_m * phi^T.
  template <int m>
  Scalar H() const {
    return Scalar(m) * G<m + 2>() - G<m + 1>();
  }

  // G_4 - 3 G_5 = 2 sum_k (-x)^k (k+1)/(2k+5)!, the third coefficient of the SE(3) block Q. The
  // difference of the two closed forms loses a few ulp below theta = 2.5, so it has its own series.
  Scalar G45() const {
    static constexpr auto coefficients = detail::g45Coefficients<11>();
    if (x_ < 6.25) return detail::alternatingSeries(x_, coefficients);
    return G<4>() - Scalar(3) * G<5>();
  }

  // Coefficient D of the inverse left Jacobian  Jl^{-1} = I - [phi]/2 + D [phi]^2,
  // D = (1 - (theta/2) cot(theta/2)) / theta^2 = (G_3 - 2 G_4) / (2 G_2): no cancellation left.
  // Where G_3 and G_4 are both closed forms (theta >= 1.5), D = (2 G_2 - G_1)/(2 G_2 theta^2) is
  // the same arithmetic with one division instead of three.
  Scalar jlInvD() const {
    if (x_ >= Scalar(2.25)) return (Scalar(2) * g2_ - g1_) / (Scalar(2) * g2_ * x_);
    return (G<3>() - Scalar(2) * G<4>()) / (Scalar(2) * g2_);
  }

 private:
  // theta^2 up to which G_1 and G_2 are summed as series in the half angle: pi^2.
  static constexpr double kHalfAngleSeriesX = 9.869604401089358;
  static constexpr double kTinyX = 1e-10;
  Scalar x_;
  Scalar g1_;
  Scalar g2_;
};

}  // namespace lie
