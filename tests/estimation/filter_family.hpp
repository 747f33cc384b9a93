// What the ESKF, the InEKF and the TSIF (section 57.5, one params block: FilterParams) are
// tested on alike: the contract's bad inputs, each refused with its message and nothing changed,
// the family's parameter checks, the noiseless trot, and the Monte Carlo NEES of a filter started
// from an error drawn from its own prior. Each filter's test file says what it expects of these.
#pragma once

#include <catch2/catch.hpp>

#include <functional>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "estimation/estimator.hpp"
#include "estimation/invariant/filter_params.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/consistency.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "lie/so3.hpp"
#include "trot_log.hpp"

namespace legkit::test {

inline Eigen::Vector3d normal3(std::mt19937& gen, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  return {n(gen), n(gen), n(gen)};
}

// Resets `filter` on 1.5 s of the trot (seed 2), steps it 1.4 s and returns the next sample with
// two feet down: room for every fault of stepFaults().
template <class Filter>
StepInput stepToTwoFeet(Filter& filter) {
  const io::Log log = trotLog(1.5, 2, false);
  const std::vector<StepInput> inputs = inputsOf(log);
  filter.reset(eval::initialState(log));
  std::size_t k = 0;
  for (; k < 1400; ++k) filter.step(inputs[k]);
  while (inputs[k].num_contacts < 2) ++k;
  return inputs[k];
}

// Steps `filter` on one spoiled copy of `good` per fault of estimation/estimator.hpp's input
// contract: each throws its message with the time, and `untouched()` checks that nothing
// changed. Then `good` itself is accepted.
template <class Filter, class Check>
void checkStepFaultsRefused(Filter& filter, const StepInput& good, const Check& untouched) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Fault {
    const char* message;
    std::function<void(StepInput&)> spoil;
  };
  const std::vector<Fault> faults = {
      {"gyro reading w_m is not finite", [&](StepInput& in) { in.imu.w_m.x() = nan; }},
      {"accelerometer reading a_m is not finite", [&](StepInput& in) { in.imu.a_m.z() = inf; }},
      {"dt must be finite and non-negative", [](StepInput& in) { in.dt = -1e-3; }},
      {"dt must be finite and non-negative", [&](StepInput& in) { in.dt = nan; }},
      {"time t is not finite", [&](StepInput& in) { in.t = nan; }},
      {"foot id 8 is out of range", [](StepInput& in) { in.contacts[1].foot = 8; }},
      {"foot id -1 is out of range", [](StepInput& in) { in.contacts[0].foot = -1; }},
      {"appears twice", [](StepInput& in) { in.contacts[1].foot = in.contacts[0].foot; }},
      {"p_body is not finite", [&](StepInput& in) { in.contacts[1].p_body.y() = nan; }},
      {"covariance is not finite", [&](StepInput& in) { in.contacts[0].cov(2, 2) = nan; }},
      {"covariance is not symmetric", [](StepInput& in) { in.contacts[1].cov(0, 1) += 1e-4; }},
      {"covariance is not positive definite",
       [](StepInput& in) { in.contacts[0].cov = -in.contacts[0].cov; }},
      {"covariance is not positive definite",
       [](StepInput& in) { in.contacts[0].cov(2, 2) = -in.contacts[0].cov(2, 2); }},
      {"num_contacts = 9 is out of range", [](StepInput& in) { in.num_contacts = 9; }},
      {"num_contacts = -1 is out of range", [](StepInput& in) { in.num_contacts = -1; }},
  };
  for (const Fault& f : faults) {
    StepInput bad = good;
    f.spoil(bad);
    INFO(f.message);
    CHECK_THROWS_WITH(filter.step(bad), Catch::Contains(f.message) && Catch::Contains("t = "));
    untouched();
  }
  CHECK_NOTHROW(filter.step(good));
}

// The family's parameter checks (invariant::checkFilterParams): a filter built from Params with
// one value of its FilterParams spoiled throws naming it.
template <class Filter, class Params>
void checkFamilyParamsRefused() {
  const double inf = std::numeric_limits<double>::infinity();
  const auto refuses = [](const std::function<void(invariant::FilterParams&)>& spoil,
                          const char* name) {
    Params params;
    spoil(params);
    INFO(name);
    CHECK_THROWS_WITH(Filter(params), Catch::Contains(name));
  };
  refuses([](invariant::FilterParams& p) { p.foot_stance_density = -1.0; }, "foot_stance_density");
  refuses([](invariant::FilterParams& p) { p.imu.gyro_noise_density = -1.0; },
          "gyro noise density");
  refuses([](invariant::FilterParams& p) { p.imu.accel_bias_random_walk = std::nan(""); },
          "accelerometer bias random walk");
  refuses([](invariant::FilterParams& p) { p.sigma_attitude = 0.0; }, "prior sigma_attitude");
  refuses([](invariant::FilterParams& p) { p.sigma_position = 0.0; }, "prior sigma_position");
  refuses([&](invariant::FilterParams& p) { p.gravity.z() = inf; }, "gravity");
}

// How a filter's attitude error enters the truth: R = R_hat Exp(e) (kLocal: the ESKF, the TSIF)
// or R = Exp(e) R_hat (kWorld: the right-invariant EKF).
enum class AttitudeError { kLocal, kWorld };

struct NeesResult {
  int runs = 0;
  double mean = 0.0;      // mean over rows of ANEES_k (9 dof)
  double fraction = 0.0;  // of rows whose ANEES_k is inside the 95 % bounds
  double above = 0.0;     // of rows whose ANEES_k is above them (over-confident)
  eval::ChiSquareBounds bounds;
};

// `runs` runs of 5 s of the Go2-class trot with their own seeds. Each run's initial biases and
// initial estimate error are drawn from the prior the filter is given (its sigmas times
// prior_scale, both in the filter and in the draw), so the claimed covariance is right at t = 0
// and NEES measures how well the filter keeps it right.
template <class Filter, class Params>
NeesResult monteCarloNees(int runs, Params params, double prior_scale,
                          const FrontendNoise& frontend, AttitudeError convention) {
  constexpr double kDuration = 5.0;
  params.sigma_attitude *= prior_scale;
  params.sigma_velocity *= prior_scale;
  params.sigma_position *= prior_scale;
  std::vector<double> anees;  // ANEES_k, per row
  for (int run = 0; run < runs; ++run) {
    std::mt19937 gen(1000 + run);
    model::ImuBias bias;
    bias.b_g = normal3(gen, params.sigma_gyro_bias);
    bias.b_a = normal3(gen, params.sigma_accel_bias);
    const io::Log log = trotLog(kDuration, 1 + run, false, bias);
    EstimateSample x0 = eval::initialState(log);
    // Truth = estimate (+) e, so the estimate is the truth with -e applied.
    const Eigen::Matrix3d E = lie::SO3d::Exp(-normal3(gen, params.sigma_attitude)).matrix();
    const Eigen::Matrix3d R = x0.q.toRotationMatrix();
    x0.q = Eigen::Quaterniond(convention == AttitudeError::kLocal ? Eigen::Matrix3d(R * E)
                                                                  : Eigen::Matrix3d(E * R));
    x0.v -= normal3(gen, params.sigma_velocity);
    x0.p -= normal3(gen, params.sigma_position);
    Filter filter(params);
    const eval::RunResult result = eval::runOnLog(
        filter, log, LogFrontend(log.layout, model::QuadrupedKinematics(), frontend), x0);
    if (anees.empty()) anees.assign(result.nees.size(), 0.0);
    for (std::size_t k = 0; k < anees.size(); ++k) anees[k] += result.nees[k] / runs;
  }
  NeesResult r;
  r.runs = runs;
  r.bounds = eval::aneesBounds(9, runs);
  int inside = 0, above = 0;
  for (const double a : anees) {
    r.mean += a / anees.size();
    inside += a >= r.bounds.lower && a <= r.bounds.upper;
    above += a > r.bounds.upper;
  }
  r.fraction = static_cast<double>(inside) / anees.size();
  r.above = static_cast<double>(above) / anees.size();
  return r;
}

// The noiseless trot (5 s, seed 1) from its first true state: the filter tracks it to 5 mm,
// 5 mm/s and 0.05 deg of tilt and of yaw, and its last sample's feet are the log's contacts
// (inContact(filter, i): whether the filter holds foot i in contact, in its own terms).
template <class Filter, class InContact>
void checkNoiselessTrotTracked(Filter& filter, const InContact& inContact) {
  const io::Log log = trotLog(5.0, 1, true);
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  const eval::RunResult run = eval::runOnLog(filter, log, frontend, eval::initialState(log));
  const eval::Metrics m = eval::compare(log, run.trajectory);
  INFO("position RMSE " << m.position_rmse << " m, velocity RMSE " << m.velocity_rmse
                        << " m/s, tilt " << m.tilt_rmse_deg << " deg, yaw " << m.yaw_rmse_deg
                        << " deg");
  CHECK(m.position_rmse < 5e-3);
  CHECK(m.velocity_rmse < 5e-3);
  CHECK(m.tilt_rmse_deg < 0.05);
  CHECK(m.yaw_rmse_deg < 0.05);
  for (int i = 0; i < io::kNumLegs; ++i)
    CHECK(inContact(filter, i) == static_cast<bool>(log.rows.back().contact[i]));
}

// The noise model of the simulator: its feet are points that never slip, so the contact-point
// sigma of the front end is tiny (and so is the stance-foot random walk each test sets).
inline FrontendNoise simulatorFrontend() {
  FrontendNoise noise;
  noise.foot_point_sigma = 5e-4;
  return noise;
}

inline std::string describe(const NeesResult& r) {
  std::ostringstream os;
  os << "ANEES per dof over " << r.runs << " runs: mean " << r.mean / 9 << ", bounds ["
     << r.bounds.lower / 9 << ", " << r.bounds.upper / 9 << "], " << 100 * r.fraction
     << " % of rows inside, " << 100 * r.above << " % above";
  return os.str();
}

}  // namespace legkit::test
