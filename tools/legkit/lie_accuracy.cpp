#include "lie_accuracy.hpp"

#include "output.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <lie/so3_series.hpp>
#include <vector>

namespace legkit::tools {
namespace {

// Where lie::AngleSeries switches from the Taylor series to the closed form (so3_series.hpp);
// written into the CSV so that the plot can mark them.
constexpr double kSwitchG3 = 1.0;
constexpr double kSwitchG4 = 1.5;
constexpr double kSwitchG5 = 2.5;

// sum_k (-x)^k c_k in long double, Horner from the smallest term. With x <= pi^2 and 40 terms
// the first omitted term is below 1e-40, and no partial sum cancels by more than a factor ~10,
// so the result is good to about 1e-18 relative: two digits beyond double's 1.1e-16.
template <typename Coef>
long double series(long double x, Coef coef) {
  long double sum = 0.0L;
  for (int k = 39; k >= 0; --k) sum = coef(k) - x * sum;
  return sum;
}

long double inverseFactorial(int n) {
  long double f = 1.0L;
  for (int i = 2; i <= n; ++i) f *= i;
  return 1.0L / f;
}

struct Row {
  double theta;
  double g3Naive, g3Lie, g4Naive, g4Lie, cNaive, cLie;
};

double relativeError(double value, long double reference) {
  return static_cast<double>(std::fabs((static_cast<long double>(value) - reference) / reference));
}

Row evaluate(double theta) {
  const double x = theta * theta;
  const long double xl = static_cast<long double>(theta) * static_cast<long double>(theta);
  // References: G_m = sum (-x)^k / (2k+m)!, and (G_4 - 3 G_5)/2 = sum (-x)^k (k+1) / (2k+5)!
  // (the two series combined term by term, so the reference itself never cancels).
  const long double g3Ref = series(xl, [](int k) { return inverseFactorial(2 * k + 3); });
  const long double g4Ref = series(xl, [](int k) { return inverseFactorial(2 * k + 4); });
  const long double cRef = series(
      xl, [](int k) { return static_cast<long double>(k + 1) * inverseFactorial(2 * k + 5); });

  // The closed forms as a textbook writes them, evaluated in double.
  const double s = std::sin(theta), c = std::cos(theta);
  const double g3Naive = (theta - s) / (theta * x);
  const double g4Naive = (x / 2 + c - 1) / (x * x);
  const double cNaive = (2 * theta - 3 * s + theta * c) / (2 * theta * x * x);

  const lie::AngleSeries<double> angle(x);
  const double g3Lie = angle.G<3>();
  const double g4Lie = angle.G<4>();
  const double cLie = 0.5 * (angle.G<4>() - 3.0 * angle.G<5>());  // as in SEK3::Q

  return {theta,
          relativeError(g3Naive, g3Ref),
          relativeError(g3Lie, g3Ref),
          relativeError(g4Naive, g4Ref),
          relativeError(g4Lie, g4Ref),
          relativeError(cNaive, cRef),
          relativeError(cLie, cRef)};
}

}  // namespace

int lieAccuracy(std::ostream& out, const std::string& csvPath, int points) {
  points = std::max(points, 2);
  const double lo = std::log10(1e-10), hi = std::log10(M_PI);
  std::vector<Row> rows;
  rows.reserve(points);
  for (int i = 0; i < points; ++i) {
    const double theta = i + 1 == points ? M_PI : std::pow(10.0, lo + (hi - lo) * i / (points - 1));
    rows.push_back(evaluate(theta));
  }

  auto worst = [&](double Row::*field) {
    double m = 0.0;
    for (const Row& r : rows) m = std::max(m, r.*field);
    return m;
  };
  out << "relative error against a long-double series, theta in [1e-10, pi], " << points
      << " points (worst case over the grid; double's unit roundoff is 1.1e-16)\n\n"
      << std::left << std::setw(54) << "  coefficient" << std::setw(14) << "naive form"
      << "lie::AngleSeries\n"
      << std::scientific << std::setprecision(1);
  auto line = [&](const char* name, double Row::*naive, double Row::*lie) {
    out << std::setw(54) << name << std::setw(14) << worst(naive) << worst(lie) << "\n";
  };
  line("  G_3 = (t - sin t)/t^3", &Row::g3Naive, &Row::g3Lie);
  line("  G_4 = (t^2/2 + cos t - 1)/t^4", &Row::g4Naive, &Row::g4Lie);
  line("  (G_4 - 3 G_5)/2 = (2t - 3 sin t + t cos t)/(2t^5)", &Row::cNaive, &Row::cLie);

  if (csvPath.empty()) return 0;
  writeAtomically(csvPath, [&](std::ostream& csv) {
    csv << "# lie::AngleSeries Taylor switch points (theta): series below, closed form above\n"
        << "# switch G3 " << kSwitchG3 << "\n# switch G4 " << kSwitchG4 << "\n# switch G5 "
        << kSwitchG5 << "\n"
        << "theta,g3_naive,g3_lie,g4_naive,g4_lie,cq_naive,cq_lie\n"
        << std::setprecision(17);
    for (const Row& r : rows) {
      csv << r.theta << ',' << r.g3Naive << ',' << r.g3Lie << ',' << r.g4Naive << ',' << r.g4Lie
          << ',' << r.cNaive << ',' << r.cLie << '\n';
    }
  });  // throws OutputError (exit 2) when the file cannot be written
  out << "\n  wrote " << rows.size() << " rows to " << csvPath << "\n";
  return 0;
}

}  // namespace legkit::tools
