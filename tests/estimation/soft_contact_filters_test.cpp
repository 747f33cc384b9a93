// Soft contact in the four filters (section 57.6, eq. Q_f): a stance foot of contact probability
// p_c gets the foot process noise density p_c sigma_stance^2 + (1 - p_c) sigma_swing^2.
//  - p_c = 1 is the hard contact: the filters run exactly as without p_c;
//  - p_c -> 0: the foot's position covariance grows as a swing foot's does;
//  - p_c = 0.8 on every foot of the analytic trot: NEES stays within its chi-square bounds.
#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "estimation/contact/soft_contact.hpp"
#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/invariant/tsif.hpp"
#include "estimation/linear_kf/linear_kf.hpp"
#include "eval/consistency.hpp"
#include "eval/runner.hpp"
#include "trot_log.hpp"

using Eigen::Matrix3d;
using Eigen::Vector3d;
using legkit::ContactMeasurement;
using legkit::EstimateSample;
using legkit::Estimator;
using legkit::StepInput;
using legkit::invariant::Eskf;
using legkit::invariant::EskfParams;
using legkit::invariant::InvariantEkf;
using legkit::invariant::InvariantEkfParams;
using legkit::invariant::Tsif;
using legkit::invariant::TsifParams;
using legkit::linear_kf::LinearKf;
using legkit::linear_kf::LinearKfParams;

namespace {

std::unique_ptr<Estimator> makeFilter(const std::string& name) {
  if (name == "linear-kf") return std::make_unique<LinearKf>();
  if (name == "eskf") return std::make_unique<Eskf>();
  if (name == "invariant-ekf") return std::make_unique<InvariantEkf>();
  return std::make_unique<Tsif>();
}

const std::vector<std::string> kFilters = {"linear-kf", "eskf", "invariant-ekf", "tsif"};

// Runs a filter over inputs, every stance foot given probability p_c (negative: left as given).
std::vector<EstimateSample> run(Estimator& filter, const EstimateSample& x0,
                                std::vector<StepInput> inputs, double p_c,
                                std::vector<legkit::BaseCovariance>* covariances = nullptr) {
  filter.reset(x0);
  std::vector<EstimateSample> out;
  for (StepInput& in : inputs) {
    for (int c = 0; c < in.num_contacts; ++c) {
      if (p_c >= 0.0) in.contacts[c].probability = p_c;
    }
    filter.step(in);
    out.push_back(filter.estimate());
    if (covariances) covariances->push_back(*filter.covariance());
  }
  return out;
}

bool identical(const EstimateSample& a, const EstimateSample& b) {
  return a.p == b.p && a.v == b.v && a.q.coeffs() == b.q.coeffs();
}

// A robot at rest, level: the accelerometer reads -g, the gyro nothing.
StepInput atRest(double t, double dt) {
  StepInput in;
  in.t = t;
  in.dt = dt;
  in.imu.w_m.setZero();
  in.imu.a_m = -legkit::model::gravity();
  return in;
}

}  // namespace

TEST_CASE("soft contact: p_c = 1 is the hard contact, bit for bit", "[57.6][soft_contact]") {
  const legkit::io::Log log = legkit::test::trotLog(2.0, 3, false);
  const std::vector<StepInput> inputs = legkit::test::inputsOf(log);
  const EstimateSample x0 = legkit::eval::initialState(log);
  for (const std::string& name : kFilters) {
    INFO(name);
    const auto filter = makeFilter(name);
    std::vector<legkit::BaseCovariance> P_given, P_one, P_below;
    const std::vector<EstimateSample> given = run(*filter, x0, inputs, -1.0, &P_given);
    const std::vector<EstimateSample> one = run(*filter, x0, inputs, 1.0, &P_one);
    // A p_c just below one must change the run: the filters do read it.
    const std::vector<EstimateSample> below = run(*filter, x0, inputs, 0.999, &P_below);
    bool same = true, differs = false;
    for (std::size_t k = 0; k < given.size(); ++k) {
      same = same && identical(given[k], one[k]) && P_given[k].P == P_one[k].P;
      differs = differs || !(P_given[k].P == P_below[k].P);
    }
    CHECK(same);
    CHECK(differs);
  }
}

// One foot touches down (a normal kinematics covariance), then stays in stance for 0.1 s with a
// measurement covariance of 1e6 m^2, so that the updates barely touch the foot's covariance and
// what remains is the process noise: at p_c = 0 the swing density, at p_c = 1 the stance one.
TEST_CASE("soft contact: p_c -> 0 lets a stance foot's covariance grow like a swing foot's",
          "[57.6][soft_contact]") {
  constexpr double kDt = 1e-3, kSteps = 100;
  const Vector3d foot(0.19, 0.14, -0.3);
  // Trace of the 3x3 foot block of a filter's covariance.
  using FootVariance = std::function<double(const Estimator&)>;
  const auto eskfFoot = [](const Estimator& f) {
    return static_cast<const Eskf&>(f)
        .P()
        .block<3, 3>(legkit::invariant::eskf::footIndex(0), legkit::invariant::eskf::footIndex(0))
        .trace();
  };
  const auto linearFoot = [](const Estimator& f) {
    const int d = legkit::linear_kf::footIndex(0);
    return static_cast<const LinearKf&>(f).P().block<3, 3>(d, d).trace();
  };
  const auto tsifFoot = [](const Estimator& f) {
    const int d = legkit::invariant::tsif::footIndex(0);
    return static_cast<const Tsif&>(f).P().block<3, 3>(d, d).trace();
  };
  const auto inekfFoot = [](const Estimator& f) {
    const auto& inekf = static_cast<const InvariantEkf&>(f);
    const int at = 3 + 3 * inekf.columnOf(0);
    return inekf.P().block<3, 3>(at, at).trace();
  };
  struct Case {
    std::string name;
    FootVariance variance;
    double stance, swing;  // densities [m/sqrt(s)]
    bool swing_state;      // the filter keeps a state for a swing foot
  };
  const std::vector<Case> cases = {
      {"linear-kf", linearFoot, LinearKfParams{}.foot_stance_density,
       LinearKfParams{}.foot_swing_density, true},
      {"eskf", eskfFoot, EskfParams{}.foot_stance_density, EskfParams{}.foot_swing_density, true},
      {"invariant-ekf", inekfFoot, InvariantEkfParams{}.foot_stance_density,
       InvariantEkfParams{}.foot_swing_density, false},
      {"tsif", tsifFoot, TsifParams{}.foot_stance_density, TsifParams{}.foot_swing_density, true}};
  for (const Case& c : cases) {
    INFO(c.name);
    // Growth of the foot block's trace over the 0.1 s after touchdown: in stance at p_c, or in
    // swing (p_c < 0 here).
    const auto growth = [&](double p_c) {
      const auto filter = makeFilter(c.name);
      EstimateSample x0;
      x0.p = Vector3d(0.0, 0.0, 0.3);
      filter->reset(x0);
      StepInput in = atRest(0.0, 0.0);
      in.contacts[0] = ContactMeasurement{0, foot, 1e-4 * Matrix3d::Identity(), std::nullopt};
      in.num_contacts = 1;
      filter->step(in);  // touchdown
      in = atRest(kDt, kDt);
      in.contacts[0] = ContactMeasurement{0, foot, 1e6 * Matrix3d::Identity(), std::nullopt};
      in.contacts[0].probability = p_c < 0.0 ? 1.0 : p_c;
      in.num_contacts = 1;
      filter->step(in);  // the first interval still carries the touchdown sample's p_c = 1
      const double before = c.variance(*filter);
      for (int k = 2; k < kSteps + 2; ++k) {
        StepInput next = in;
        next.t = k * kDt;
        if (p_c < 0.0) next.num_contacts = 0;
        filter->step(next);
      }
      return c.variance(*filter) - before;
    };
    const double T = kSteps * kDt;
    const double swing = 3.0 * c.swing * c.swing * T;  // trace of sigma_swing^2 T I
    const double stance = 3.0 * c.stance * c.stance * T;
    const double at_zero = growth(0.0), at_one = growth(1.0), at_half = growth(0.5);
    CAPTURE(at_zero, at_one, at_half, swing, stance);
    CHECK(at_zero == Approx(swing).epsilon(0.01));
    CHECK(at_half == Approx(legkit::contact::softFootNoiseDensity(0.5, c.stance, c.swing) * 3 * T)
                         .epsilon(0.01));
    CHECK(at_one < 1e-3 * swing);
    if (c.swing_state) CHECK(growth(-1.0) == Approx(at_zero).epsilon(0.01));
  }
}

namespace {

// ANEES_k (per row, mean over runs) of M runs of 5 s of the trot, seeds 1.., each with its
// initial biases and estimate error drawn from the filter's prior (as the ESKF NEES tests do).
struct Nees {
  double mean = 0.0;      // mean over rows of ANEES_k
  double fraction = 0.0;  // of rows inside the 95 % bounds
  legkit::eval::ChiSquareBounds bounds;
};

Nees monteCarloNees(const std::string& name, int runs, double p_c) {
  const EskfParams prior;  // the ESKF's and the InEKF's default prior sigmas are the same
  std::vector<double> anees;
  int dof = 0;
  for (int r = 0; r < runs; ++r) {
    std::mt19937 gen(2000 + r);
    std::normal_distribution<double> n01;
    const auto normal3 = [&](double s) {
      return Vector3d(s * n01(gen), s * n01(gen), s * n01(gen));
    };
    legkit::model::ImuBias bias;
    bias.b_g = normal3(prior.sigma_gyro_bias);
    bias.b_a = normal3(prior.sigma_accel_bias);
    const legkit::io::Log log = legkit::test::trotLog(5.0, 1 + r, false, bias);
    EstimateSample x0 = legkit::eval::initialState(log);
    const Vector3d e_theta = normal3(prior.sigma_attitude);
    x0.q = Eigen::Quaterniond(x0.q.toRotationMatrix() *
                              Eigen::AngleAxisd(-e_theta.norm(), e_theta.normalized()).matrix());
    x0.v -= normal3(prior.sigma_velocity);
    x0.p -= normal3(prior.sigma_position);
    const auto filter = makeFilter(name);
    std::vector<legkit::BaseCovariance> P;
    const std::vector<EstimateSample> x = run(*filter, x0, legkit::test::inputsOf(log), p_c, &P);
    if (anees.empty()) anees.assign(x.size(), 0.0);
    for (std::size_t k = 0; k < x.size(); ++k) {
      const legkit::io::LogRow& row = log.rows[k];
      const EstimateSample truth{row.t, row.gt_q, row.gt_v, row.gt_p};
      anees[k] += legkit::eval::nees(truth, x[k], P[k]) / runs;
    }
    dof = legkit::eval::neesDof(P.back());
  }
  Nees r;
  r.bounds = legkit::eval::aneesBounds(dof, runs);
  int inside = 0;
  for (const double a : anees) {
    r.mean += a / anees.size();
    inside += a >= r.bounds.lower && a <= r.bounds.upper;
  }
  r.fraction = static_cast<double>(inside) / anees.size();
  return r;
}

}  // namespace

// Measured (these seeds): mean NEES 8.42 for both filters (9 dof; bounds [6.56, 11.81] for 10
// runs), 96 % of rows inside. At p_c = 0.8 a stance foot's density is 0.8 sigma_stance^2 +
// 0.2 sigma_swing^2, about 0.8 m^2/s: the feet are nearly free, the legs say little, and what the
// filter claims it still knows is right.
TEST_CASE("soft contact: p_c = 0.8 on every stance foot keeps the ESKF and the InEKF consistent",
          "[57.6][soft_contact][nees]") {
  for (const std::string name : {"eskf", "invariant-ekf"}) {
    const Nees r = monteCarloNees(name, 10, 0.8);
    WARN(name << ", p_c = 0.8: mean NEES " << r.mean << ", bounds [" << r.bounds.lower << ", "
              << r.bounds.upper << "], " << 100 * r.fraction << " % of rows inside");
    CHECK(r.mean > r.bounds.lower);
    CHECK(r.mean < r.bounds.upper);
  }
}

TEST_CASE("soft contact: a probability outside [0, 1] or NaN is refused, naming field and time",
          "[57.6][soft_contact]") {
  for (const std::string& name : kFilters) {
    INFO(name);
    const auto filter = makeFilter(name);
    for (const double p_c : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
      StepInput in = atRest(2.5, 0.0);
      in.contacts[0] = ContactMeasurement{1, Vector3d(0.19, -0.14, -0.3),
                                          1e-4 * Matrix3d::Identity(), std::nullopt};
      in.contacts[0].probability = p_c;
      in.num_contacts = 1;
      CHECK_THROWS_WITH(filter->step(in), Catch::Contains("probability") &&
                                              Catch::Contains("t = 2.5") &&
                                              Catch::Contains("foot id 1"));
    }
    StepInput edge = atRest(2.5, 0.0);
    edge.contacts[0] = ContactMeasurement{1, Vector3d(0.19, -0.14, -0.3),
                                          1e-4 * Matrix3d::Identity(), std::nullopt};
    edge.contacts[0].probability = 0.0;
    edge.num_contacts = 1;
    CHECK_NOTHROW(filter->step(edge));
  }
}
