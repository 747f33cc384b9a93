// NEES, chi-square quantiles and ANEES bounds, and the Monte Carlo runner's bookkeeping.
#include <catch2/catch.hpp>
#include <cmath>

#include "eval/consistency.hpp"
#include "eval/monte_carlo.hpp"

using namespace legkit;

TEST_CASE("chi-square quantiles match published tables", "[eval]") {
  // Abramowitz and Stegun, table 26.8 / any statistics table.
  CHECK(eval::chiSquareQuantile(0.975, 9) == Approx(19.0228).epsilon(1e-5));
  CHECK(eval::chiSquareQuantile(0.025, 9) == Approx(2.70039).epsilon(1e-5));
  CHECK(eval::chiSquareQuantile(0.95, 1) == Approx(3.84146).epsilon(1e-5));
  CHECK(eval::chiSquareQuantile(0.5, 2) == Approx(2.0 * std::log(2.0)).epsilon(1e-10));
  CHECK(eval::chiSquareQuantile(0.99, 100) == Approx(135.807).epsilon(1e-5));
  CHECK_THROWS_AS(eval::chiSquareQuantile(1.0, 3), std::invalid_argument);
  CHECK_THROWS_AS(eval::chiSquareQuantile(0.5, 0), std::invalid_argument);
}

TEST_CASE("ANEES bounds narrow around the dimension as runs are added", "[eval]") {
  const auto b1 = eval::aneesBounds(9, 1);
  CHECK(b1.lower == Approx(2.70039).epsilon(1e-5));
  CHECK(b1.upper == Approx(19.0228).epsilon(1e-5));
  const auto b50 = eval::aneesBounds(9, 50);  // chi2(450) / 50
  CHECK(b50.lower == Approx(7.86).epsilon(2e-3));
  CHECK(b50.upper == Approx(10.21).epsilon(2e-3));
  CHECK(b50.lower < 9.0);
  CHECK(b50.upper > 9.0);
}

TEST_CASE("NEES weighs each component by the claimed covariance", "[eval]") {
  EstimateSample truth, est;
  truth.p = Eigen::Vector3d(0.2, 0.0, 0.0);
  truth.v = Eigen::Vector3d(0.0, 0.1, 0.0);
  const Eigen::Vector3d dtheta(0.0, 0.0, 0.03);
  truth.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitZ()));
  BaseCovariance cov;
  cov.P.diagonal() << 1e-4, 1e-4, 1e-4, 0.01, 0.01, 0.01, 0.04, 0.04, 0.04;
  const Eigen::Matrix<double, 9, 1> e = eval::baseError(truth, est);
  CHECK(e.head<3>().isApprox(dtheta, 1e-12));
  // (0.03^2 / 1e-4) + (0.1^2 / 0.01) + (0.2^2 / 0.04) = 9 + 1 + 1
  CHECK(eval::nees(truth, est, cov) == Approx(11.0).epsilon(1e-9));
  cov.has_attitude = false;  // only velocity and position count
  CHECK(eval::neesDof(cov) == 6);
  CHECK(eval::nees(truth, est, cov) == Approx(2.0).epsilon(1e-9));
  cov.P(7, 7) = -1.0;
  CHECK_THROWS_AS(eval::nees(truth, est, cov), std::invalid_argument);
}

namespace {

// Stands still at the origin claiming a fixed covariance: its NEES is a known function of the
// true trajectory, which is all the runner's bookkeeping test needs.
class StandStill final : public Estimator {
 public:
  std::string name() const override { return "stand-still"; }
  void reset(const EstimateSample& x0) override { x_ = x0; }
  void step(const StepInput& in) override { x_.t = in.t; }
  EstimateSample estimate() const override { return x_; }
  std::optional<BaseCovariance> covariance() const override { return BaseCovariance{}; }

 private:
  EstimateSample x_;
};

}  // namespace

TEST_CASE("the Monte Carlo runner averages NEES over runs, whatever the thread count", "[eval]") {
  eval::MonteCarloOptions options;
  options.sim.duration = 3.0;  // the trot starts after about 2 s of standing
  options.runs = 3;
  const std::vector<eval::NamedEstimator> estimators{
      {"stand-still", [] { return std::make_unique<StandStill>(); }}};
  options.threads = 1;
  const auto one = eval::monteCarlo(options, estimators);
  options.threads = 2;
  const auto two = eval::monteCarlo(options, estimators);
  REQUIRE(one.size() == 1);
  REQUIRE(one[0].runs.size() == 3);
  REQUIRE(one[0].anees.size() == one[0].t.size());
  CHECK(one[0].dof == 9);
  CHECK(one[0].anees == two[0].anees);
  // With P = I the NEES is |e|^2: zero at the start (reset to the truth), growing as the
  // trotting robot walks away from the estimate that stands still.
  CHECK(one[0].anees.front() == Approx(0.0).margin(1e-12));
  CHECK(one[0].anees.back() > 0.0);
  CHECK(one[0].bounds.lower == Approx(eval::aneesBounds(9, 3).lower));
  options.runs = 0;
  CHECK_THROWS_AS(eval::monteCarlo(options, estimators), std::invalid_argument);
}

TEST_CASE("the Monte Carlo prior draws each run's initial error and IMU biases, reproducibly",
          "[eval]") {
  eval::MonteCarloOptions options;
  options.sim.duration = 0.2;  // standing: the gyro reads its bias plus noise
  options.runs = 4;
  const std::vector<eval::NamedEstimator> estimators{
      {"stand-still", [] { return std::make_unique<StandStill>(); }}};
  // Per run: the initial velocity error, and the mean gyro reading over the standing log.
  const auto draws = [&](int threads, bool prior) {
    std::vector<Eigen::Vector3d> dv(options.runs), gyro(options.runs);
    options.threads = threads;
    options.prior.reset();
    if (prior) options.prior = eval::InitialPrior{};
    options.on_run = [&](int run, std::size_t, const io::Log& log, const eval::RunResult& r) {
      dv[run] = r.trajectory.front().v - log.rows.front().gt_v;
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (const io::LogRow& row : log.rows) sum += row.gyro;
      gyro[run] = sum / static_cast<double>(log.rows.size());
    };
    eval::monteCarlo(options, estimators);
    return std::make_pair(dv, gyro);
  };
  const auto [dv, gyro] = draws(1, true);
  const auto [dv2, gyro2] = draws(2, true);
  const auto [dv0, gyro0] = draws(1, false);
  CHECK(dv == dv2);  // the draw belongs to the run, not to the thread
  CHECK(gyro == gyro2);
  const double sigma_bg = eval::InitialPrior{}.gyro_bias, sigma_v = eval::InitialPrior{}.velocity;
  for (int j = 0; j < options.runs; ++j) {
    CAPTURE(j);
    CHECK(dv0[j].norm() == 0.0);  // without a prior, every run starts from the truth
    CHECK(dv[j].norm() > 0.0);
    CHECK(dv[j].cwiseAbs().maxCoeff() < 5 * sigma_v);
    // Same seed, same noise: the readings differ by the drawn (constant) bias plus its random
    // walk over 0.2 s, which is far smaller.
    const Eigen::Vector3d bias = gyro[j] - gyro0[j];
    CHECK(bias.norm() > 1e-2 * sigma_bg);
    CHECK(bias.cwiseAbs().maxCoeff() < 5 * sigma_bg);
  }
  CHECK(dv[0] != dv[1]);
}
