#include "tour.hpp"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <lie/lie.hpp>
#include <random>
#include <vector>

namespace legkit::tools {
namespace {

using SE6 = lie::SEK3<double, 6>;  // R, v, p and four feet: the quadruped InEKF state

struct Check {
  const char* identity;
  double residual;
  double tol;
};

// Nanoseconds per call of f over n pre-generated inputs.
template <typename F>
double nsPerCall(int n, F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < n; ++i) f(i);
  const auto t1 = std::chrono::steady_clock::now();
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / n;
}

}  // namespace

int lieTour(std::ostream& out, unsigned seed) {
  std::mt19937 gen(seed);
  std::normal_distribution<double> n01;
  const SE6 X = SE6::Random(gen, 2.0), Y = SE6::Random(gen, 2.0);
  SE6::Tangent xi;
  for (int i = 0; i < xi.size(); ++i) xi(i) = n01(gen);
  const Eigen::Vector3d nearPi = (M_PI - 1e-7) * Eigen::Vector3d(1, 2, 2).normalized();
  const Eigen::Vector3d tiny = 1e-9 * Eigen::Vector3d(0.3, -0.4, 0.5);

  const std::vector<Check> checks = {
      {"SE_6(3): Log(Exp(xi)) = xi", (SE6::Exp(xi).Log() - xi).cwiseAbs().maxCoeff(), 1e-12},
      {"SE_6(3): X Exp(xi) X^-1 = Exp(Ad_X xi)",
       ((X * SE6::Exp(xi) * X.inverse()).matrix() - SE6::Exp(X.Adj() * xi).matrix())
           .cwiseAbs()
           .maxCoeff(),
       1e-10},
      {"SE_6(3): Ad_{XY} = Ad_X Ad_Y",
       ((X * Y).Adj() - X.Adj() * Y.Adj()).cwiseAbs().maxCoeff(), 1e-10},
      {"SE_6(3): Jr(xi) Jr(xi)^-1 = I",
       (SE6::Jr(xi) * SE6::JrInv(xi) - SE6::Jacobian::Identity()).cwiseAbs().maxCoeff(), 1e-12},
      {"SO(3) near pi: Exp(Log(R)) = R",
       (lie::SO3d::Exp(lie::SO3d::Exp(nearPi).Log()).matrix() - lie::SO3d::Exp(nearPi).matrix())
           .cwiseAbs()
           .maxCoeff(),
       1e-12},
      {"SO(3) at 1e-9 rad: Log(Exp(phi)) = phi (relative)",
       (lie::SO3d::Exp(tiny).Log() - tiny).norm() / tiny.norm(), 1e-12},
  };

  out << "legkit tour of lie/ (seed " << seed << ")\n\n";
  bool ok = true;
  for (const Check& c : checks) {
    const bool pass = c.residual <= c.tol;
    ok = ok && pass;
    out << "  " << (pass ? "ok  " : "FAIL") << "  " << std::left << std::setw(52) << c.identity
        << " residual " << std::scientific << std::setprecision(1) << c.residual << "\n";
  }

  constexpr int n = 1024;
  std::vector<SE6::Tangent> xs(n);
  std::vector<SE6> Xs(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < xi.size(); ++j) xs[i](j) = n01(gen);
    Xs[i] = SE6::Random(gen, 2.0);
  }
  double sink = 0.0;
  const int reps = 200;
  const double tExp = nsPerCall(n * reps, [&](int i) { sink += SE6::Exp(xs[i % n]).R()(0, 0); });
  const double tLog = nsPerCall(n * reps, [&](int i) { sink += Xs[i % n].Log()(0); });
  const double tMul = nsPerCall(n * reps, [&](int i) { sink += (Xs[i % n] * Xs[(i + 1) % n]).R()(1, 1); });
  out << "\n  time per call on this machine (bench/ measures properly):\n" << std::fixed
      << std::setprecision(0) << "    SE_6(3) Exp " << tExp << " ns, Log " << tLog
      << " ns, compose " << tMul << " ns   (checksum " << std::setprecision(3) << sink << ")\n";
  out << "\n" << (ok ? "every identity holds" : "SOME IDENTITIES FAILED") << "\n";
  return ok ? 0 : 1;
}

}  // namespace legkit::tools
