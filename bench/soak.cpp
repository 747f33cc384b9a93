// legkit-soak: runs each filter for many steps (10^7 by default) on the default trot replayed
// lap after lap, with the health checks of the Estimator contract on, and reports what rounding
// does to it over that long: the worst asymmetry of P (relative to its largest diagonal entry),
// the worst orthonormality error of the attitude, ||R^T R - I||_max, whether P stayed positive
// definite (an LDLT every 1000 steps and at the end), and the health record.
//
//   build/bench/legkit-soak [--steps N]
//
// Exit status 1 if any filter lost positive definiteness or had to recover.
#include <Eigen/Cholesky>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/invariant/tsif.hpp"
#include "estimation/linear_kf/linear_kf.hpp"
#include "trot_inputs.hpp"

namespace legkit::bench {
namespace {

struct Soak {
  double worst_asymmetry = 0.0;       // max |P - P^T| / max diag P
  double worst_orthonormality = 0.0;  // max |R^T R - I|
  bool always_spd = true;
  Health health;
};

// Filter's covariance (or information) matrix and attitude matrix, read through `view`.
template <typename Filter, typename View>
Soak soak(Filter& filter, long steps, View view) {
  const TrotInputs& inputs = trotInputs();
  const double lap = inputs.steps.back().t - inputs.steps.front().t + 1e-3;
  filter.reset(inputs.x0);
  Soak s;
  for (long k = 0; k < steps; ++k) {
    const std::size_t i = static_cast<std::size_t>(k) % inputs.steps.size();
    StepInput in = inputs.steps[i];
    in.t += lap * static_cast<double>(static_cast<std::size_t>(k) / inputs.steps.size());
    if (i == 0 && k > 0) in.dt = 1e-3;  // the next lap follows on
    filter.step(in);
    const auto [P, R] = view(filter);
    const double scale = P.diagonal().cwiseAbs().maxCoeff();
    s.worst_asymmetry =
        std::max(s.worst_asymmetry, (P - P.transpose()).cwiseAbs().maxCoeff() / scale);
    s.worst_orthonormality =
        std::max(s.worst_orthonormality,
                 (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff());
    if (k % 1000 == 999 || k == steps - 1) s.always_spd = s.always_spd && isPositiveDefinite(P);
  }
  s.health = filter.health();
  return s;
}

void report(const char* name, long steps, const Soak& s) {
  std::printf("%-14s %10ld %14.2e %18.2e %5s %10llu %10llu\n", name, steps, s.worst_asymmetry,
              s.worst_orthonormality, s.always_spd ? "yes" : "NO",
              static_cast<unsigned long long>(s.health.total()),
              static_cast<unsigned long long>(s.health[Fault::kStateUnhealthy]));
}

}  // namespace
}  // namespace legkit::bench

int main(int argc, char** argv) {
  using namespace legkit;
  long steps = 10'000'000;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--steps") == 0 && i + 1 < argc) {
      steps = std::atol(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: %s [--steps N]\n", argv[0]);
      return 2;
    }
  }
  if (steps < 1) {
    std::fprintf(stderr, "legkit-soak: --steps must be a positive integer\n");
    return 2;
  }
  std::printf("%-14s %10s %14s %18s %5s %10s %10s\n", "filter", "steps", "asymmetry(P)",
              "|R^T R - I|_max", "SPD", "faults", "recoveries");
  bool ok = true;
  const auto run = [&](const char* name, auto& filter, auto view) {
    const bench::Soak s = bench::soak(filter, steps, view);
    bench::report(name, steps, s);
    ok = ok && s.always_spd && s.health.healthy();
  };
  linear_kf::LinearKf lkf;
  run("linear-kf", lkf, [](const linear_kf::LinearKf& f) {
    return std::pair<Eigen::MatrixXd, Eigen::Matrix3d>(f.P(), f.attitude().R().matrix());
  });
  invariant::Eskf eskf;
  run("eskf", eskf, [](const invariant::Eskf& f) {
    return std::pair<Eigen::MatrixXd, Eigen::Matrix3d>(f.P(), f.state().R.matrix());
  });
  invariant::InvariantEkf inekf;
  run("invariant-ekf", inekf, [](const invariant::InvariantEkf& f) {
    return std::pair<Eigen::MatrixXd, Eigen::Matrix3d>(f.P(), f.X().R());
  });
  invariant::Tsif tsif;
  run("tsif", tsif, [](const invariant::Tsif& f) {
    return std::pair<Eigen::MatrixXd, Eigen::Matrix3d>(f.P(), f.state().R.matrix());
  });
  return ok ? 0 : 1;
}
