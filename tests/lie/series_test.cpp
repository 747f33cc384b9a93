// lie::AngleSeries against long-double references: every coefficient G_1..G_6, H_1..H_4 and the
// inverse-Jacobian coefficient D, on a dense logarithmic grid of theta from 1e-12 to pi and on
// both sides of every switch point (theta^2 = pi^2: half-angle series / std::sin and std::cos for
// G_1, G_2; theta^2 = 1, 2.25, 6.25: Taylor series / closed-form recurrence of G_3 .. G_6).
//
// The references are computed in long double (64-bit mantissa, eps = 1.1e-19) from formulas
// that do not cancel at the angle where they are used:
//   G_1 = sin(theta)/theta, G_2 = 2 sin^2(theta/2)/theta^2       (no cancellation anywhere)
//   G_m, m >= 3: the defining series sum_k (-x)^k/(2k+m)!, 60 terms (terms of at most ~0.1
//                against values of ~1/m!: no significant cancellation for theta <= pi)
//   H_m = (1/theta) dG_m/dtheta = sum_{k>=1} (-1)^k 2k x^(k-1)/(2k+m)!, differentiated termwise
//   D = (1 - (theta/2) cot(theta/2))/theta^2: closed form for theta >= 1/2, and below it the
//       Bernoulli series D = sum_{n>=1} |B_2n| theta^(2n-2)/(2n)!.
// None of them uses the implementation's identities (recurrences, D = (G_3 - 2G_4)/(2G_2)).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include <lie/so3_series.hpp>

namespace {

using LD = long double;

LD factorialLD(int n) {
  LD f = 1;
  for (int i = 2; i <= n; ++i) f *= i;
  return f;
}

// G_m(x), x = theta^2.
LD gRef(int m, LD x) {
  if (m == 1) {
    if (x == 0) return 1;
    const LD t = std::sqrt(x);
    return std::sin(t) / t;
  }
  if (m == 2) {
    if (x == 0) return 0.5L;
    const LD s = std::sin(std::sqrt(x) / 2);
    return 2 * s * s / x;
  }
  LD term = 1 / factorialLD(m), sum = term;
  for (int k = 1; k < 60; ++k) {
    term *= -x / ((2 * k + m - 1) * LD(2 * k + m));
    sum += term;
  }
  return sum;
}

// H_m(x) = sum_{k>=1} (-1)^k 2k x^(k-1) / (2k+m)!.
LD hRef(int m, LD x) {
  LD b = -1 / factorialLD(m + 2), sum = 2 * b;  // k = 1
  for (int k = 1; k < 60; ++k) {
    b *= -x / ((2 * k + m + 1) * LD(2 * k + m + 2));
    sum += 2 * (k + 1) * b;
  }
  return sum;
}

// D(x) = (1 - (theta/2) cot(theta/2)) / theta^2.
LD dRef(LD x) {
  const LD t = std::sqrt(x);
  if (t >= 0.5L) return (1 - (t / 2) * std::cos(t / 2) / std::sin(t / 2)) / x;
  static const LD absB2n[] = {1.0L / 6,       1.0L / 30,      1.0L / 42, 1.0L / 30,
                              5.0L / 66,      691.0L / 2730,  7.0L / 6,  3617.0L / 510,
                              43867.0L / 798, 174611.0L / 330};
  LD sum = 0, xp = 1;
  for (int n = 1; n <= 10; ++n) {
    sum += absB2n[n - 1] * xp / factorialLD(2 * n);
    xp *= x;
  }
  return sum;
}

template <int m>
double G(double x) {
  return lie::AngleSeries<double>(x).G<m>();
}
template <int m>
double H(double x) {
  return lie::AngleSeries<double>(x).H<m>();
}

struct Coefficient {
  std::string name;
  std::function<double(double)> value;  // the implementation, at x = theta^2
  std::function<LD(LD)> reference;
};

std::vector<Coefficient> coefficients() {
  std::vector<Coefficient> c = {
      {"G1", G<1>, [](LD x) { return gRef(1, x); }},
      {"G2", G<2>, [](LD x) { return gRef(2, x); }},
      {"G3", G<3>, [](LD x) { return gRef(3, x); }},
      {"G4", G<4>, [](LD x) { return gRef(4, x); }},
      {"G5", G<5>, [](LD x) { return gRef(5, x); }},
      {"G6", G<6>, [](LD x) { return gRef(6, x); }},
      {"H1", H<1>, [](LD x) { return hRef(1, x); }},
      {"H2", H<2>, [](LD x) { return hRef(2, x); }},
      {"H3", H<3>, [](LD x) { return hRef(3, x); }},
      {"H4", H<4>, [](LD x) { return hRef(4, x); }},
      {"D", [](double x) { return lie::AngleSeries<double>(x).jlInvD(); }, dRef},
  };
  return c;
}

// The theta^2 at which AngleSeries changes formula (so3_series.hpp).
constexpr double kSwitchPoints[] = {1.0, 2.25, 6.25, M_PI* M_PI};

// theta^2 values: a log grid of theta in [1e-12, pi], the switch points with neighbours a few
// ulp and a few relative 1e-9..1e-3 away on both sides, 0, and pi^2.
std::vector<double> gridOfX() {
  std::vector<double> xs = {0.0};
  const int n = 4000;
  for (int i = 0; i <= n; ++i) {
    const double theta = std::pow(10.0, -12.0 + (std::log10(M_PI) + 12.0) * i / n);
    xs.push_back(theta * theta);
  }
  for (const double sw : kSwitchPoints) {
    double up = sw, down = sw;
    xs.push_back(sw);
    for (int k = 0; k < 4; ++k) {
      up = std::nextafter(up, 100.0);
      down = std::nextafter(down, 0.0);
      xs.push_back(up);
      xs.push_back(down);
    }
    for (const double rel : {1e-9, 1e-6, 1e-3, 1e-1}) {
      xs.push_back(sw * (1 + rel));
      xs.push_back(sw * (1 - rel));
    }
  }
  xs.push_back(M_PI * M_PI);
  return xs;
}

// How much the exact value moves when x moves by one ulp: |x f'(x)| eps. Near pi, G_1 itself
// goes to 0 while this stays ~1e-17, so no double routine can have a small relative error
// there: such points are judged against this conditioning floor instead.
LD conditioningFloor(const Coefficient& c, LD x) {
  if (x == 0) return 0;
  const LD h = 1e-7L;
  return std::abs(c.reference(x * (1 + h)) - c.reference(x * (1 - h))) / (2 * h) *
         std::numeric_limits<double>::epsilon();
}

}  // namespace

TEST_CASE("the long-double references agree with each other", "[lie][series]") {
  // Independent formulas for the same number: the series against the closed forms (where the
  // closed forms do not cancel), and D against (G_3 - 2 G_4) / (2 G_2).
  for (const LD theta : {0.7L, 1.3L, 2.5L, 3.1L, 3.14159L}) {
    const LD x = theta * theta, s = std::sin(theta), c = std::cos(theta);
    CHECK(std::abs(gRef(3, x) - (theta - s) / (x * theta)) <= 1e-17L * gRef(3, x));
    CHECK(std::abs(gRef(4, x) - (x / 2 + c - 1) / (x * x)) <= 1e-16L * gRef(4, x));
    CHECK(std::abs(hRef(1, x) - (theta * c - s) / (x * theta)) <= 1e-17L * std::abs(hRef(1, x)));
  }
  for (const LD theta : {1e-6L, 1e-3L, 0.1L, 0.49L, 0.51L, 1.0L, 3.0L}) {
    const LD x = theta * theta;
    const LD viaG = (gRef(3, x) - 2 * gRef(4, x)) / (2 * gRef(2, x));
    CHECK(std::abs(dRef(x) - viaG) <= 1e-17L * dRef(x));
  }
  // The recurrence theta^2 G_{m+2} = 1/m! - G_m, at angles where it does not cancel.
  for (const LD theta : {2.0L, 3.0L}) {
    const LD x = theta * theta;
    for (int m = 1; m <= 4; ++m) {
      CHECK(std::abs(x * gRef(m + 2, x) - (1 / factorialLD(m) - gRef(m, x))) <= 1e-17L);
    }
  }
}

TEST_CASE("AngleSeries at theta = 0 is exact", "[lie][series]") {
  const lie::AngleSeries<double> c(0.0);
  CHECK(c.G<1>() == 1.0);
  CHECK(c.G<2>() == 0.5);
  CHECK(c.G<3>() == 1.0 / 6);
  CHECK(c.G<4>() == 1.0 / 24);
  CHECK(c.G<5>() == 1.0 / 120);
  CHECK(c.G<6>() == 1.0 / 720);
  CHECK(c.jlInvD() == Approx(1.0 / 12).epsilon(1e-16));
  CHECK(c.theta2() == 0.0);
}

TEST_CASE("AngleSeries against long-double references on a dense grid", "[lie][series]") {
  // Relative error bound. Measured worst over the grid (LEGKIT_SERIES_REPORT=1 prints it):
  // 3.4e-15 for H_3 near theta = 1.6 (m G_{m+2} - G_{m+1} cancels by a factor ~3), at most
  // 1.3e-15 for every G_m, 1.9e-15 for D. 4e-15 is far below what a wrong term or a misplaced
  // switch gives (>= 1e-12). G_1 near pi is judged against the conditioning floor instead.
  const double tol = 4e-15;
  const bool verbose = std::getenv("LEGKIT_SERIES_REPORT") != nullptr;
  const std::vector<double> xs = gridOfX();
  for (const Coefficient& c : coefficients()) {
    double worst = 0, worstX = 0;
    int judgedByFloor = 0;
    for (const double x : xs) {
      const LD ref = c.reference(LD(x));
      const LD err = std::abs(LD(c.value(x)) - ref);
      const LD floor = conditioningFloor(c, x);
      const double rel = double(err / std::abs(ref));
      if (4 * floor > tol * std::abs(ref)) {
        ++judgedByFloor;
        CHECK(err <= 4 * floor);  // a few ulp of the input's conditioning
      } else if (rel > worst) {
        worst = rel;
        worstX = x;
      }
      if (!(err <= tol * std::abs(ref) || err <= 4 * floor)) {
        CAPTURE(c.name, x, std::sqrt(x), double(ref), c.value(x), rel);
        FAIL_CHECK("relative error above tolerance");
      }
    }
    if (verbose) {
      std::cout << c.name << ": worst relative error " << worst
                << " at theta = " << std::sqrt(worstX) << " (" << judgedByFloor
                << " points judged by the conditioning floor)\n";
    }
    CHECK(worst <= tol);
  }
}

// The constructor SE_K(3)'s Log uses, AngleSeries(theta, sin theta, cos theta): G_1 and G_2 by
// division (1 - cos theta = sin^2 theta/(1 + cos theta) while cos theta > 0), a two-term series
// below theta^2 = 1e-10, and everything else derived from them. Same grid and tolerance as above,
// plus both sides of its own switch theta = 1e-5 and of cos theta = 0.
TEST_CASE("AngleSeries from theta, sin theta and cos theta", "[lie][series]") {
  const double tol = 4e-15;
  std::vector<double> thetas;
  for (const double x : gridOfX()) thetas.push_back(std::sqrt(x));
  for (const double sw : {1e-5, M_PI / 2}) {
    for (const double rel : {0.0, 1e-15, 1e-9, 1e-6, 1e-3}) {
      thetas.push_back(sw * (1 + rel));
      thetas.push_back(sw * (1 - rel));
    }
  }
  const std::vector<Coefficient> all = coefficients();
  for (const double theta : thetas) {
    const lie::AngleSeries<double> a(theta, std::sin(theta), std::cos(theta));
    const LD x = LD(theta) * LD(theta);
    const double values[] = {a.G<1>(), a.G<2>(), a.G<3>(),  a.G<4>(),
                             a.G<5>(), a.G<6>(), a.jlInvD()};
    const std::size_t index[] = {0, 1, 2, 3, 4, 5, 10};  // G1..G6 and D in coefficients()
    for (int i = 0; i < 7; ++i) {
      const Coefficient& c = all[index[i]];
      const LD ref = c.reference(x);
      const LD err = std::abs(LD(values[i]) - ref);
      CAPTURE(c.name, theta, double(ref), values[i]);
      CHECK((err <= tol * std::abs(ref) || err <= 4 * conditioningFloor(c, x)));
    }
  }
}

// The switch points of AngleSeries must not leave a visible step: the values just below and
// just above agree as closely as the function's own slope allows (for G_1 at theta = pi, where
// G_1 ~ 0: within the conditioning floor of the dense test, on each side).
TEST_CASE("AngleSeries is continuous across its switch points", "[lie][series]") {
  for (const double sw : kSwitchPoints) {
    const double below = std::nextafter(sw, 0.0), above = sw;
    for (const Coefficient& c : coefficients()) {
      CAPTURE(c.name, sw);
      const double a = c.value(below), b = c.value(above);
      CHECK(std::abs(a - b) <= 4e-15 * std::abs(b) + 8 * double(conditioningFloor(c, sw)));
    }
  }
}
