#include "eval/runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "estimation/imu_extrinsic_frames.hpp"
#include "eval/consistency.hpp"
#include "eval/metrics.hpp"

namespace legkit::eval {

std::string rowLocation(const io::Log& log, std::size_t k) {
  if (log.source.empty()) return {};
  return log.source + ":" + std::to_string(log.lineOfRow(k));
}

RunFailure failureAt(const io::Log& log, std::size_t k, const std::string& what) {
  RunFailure f;
  f.what = what;
  f.row = k;
  f.t = log.rows[k].t;
  f.where = rowLocation(log, k);
  return f;
}

std::string threwReason(const std::exception& e) {
  const std::string what = e.what();
  // "<Name>::step at t = <t>: <reason>" (health_guard.cpp's checkStepInput and the estimators).
  const std::size_t step = what.find("::step at t = ");
  const std::size_t colon = step == std::string::npos ? step : what.find(": ", step);
  const bool name = step != std::string::npos && step > 0 &&
                    what.find_first_of(" :") >= step;  // one word before "::step"
  if (name && colon != std::string::npos) return "threw: " + what.substr(colon + 2);
  return "threw: " + what;
}

std::string unusableEstimate(const EstimateSample& x, const BaseCovariance* cov) {
  if (!(std::isfinite(x.t) && x.q.coeffs().allFinite() && x.v.allFinite() && x.p.allFinite())) {
    return "non-finite estimate";
  }
  if (cov && !cov->P.allFinite()) return "non-finite covariance";
  if (cov && !(cov->P.diagonal().array() >= 0.0).all()) {
    return "covariance with a negative variance on its diagonal";
  }
  return {};
}

namespace {

// The run of runOnLog: input_of(k, dt) gives row k's input (the estimator not yet stepped on
// it); after_row() runs once that row's estimate has been recorded. The estimator runs in the
// IMU frame of `extrinsic`; x0 and what is recorded are the base's.
template <typename InputOf, typename AfterRow>
RunResult runRows(Estimator& estimator, const io::Log& log, const model::ImuExtrinsic& extrinsic,
                  const EstimateSample& x0, const std::optional<Eigen::Vector3d>& gyro_bias,
                  double truth_velocity_window, const InputOf& input_of,
                  const AfterRow& after_row) {
  const bool moved = !extrinsic.isIdentity();
  RunResult result;
  result.name = estimator.name();
  result.trajectory.reserve(log.rows.size());
  std::chrono::duration<double, std::micro> busy{0};
  std::size_t steps = 0;
  std::size_t k = 0;
  const auto fail = [&](const std::string& what) {
    if (k < log.rows.size()) {
      result.failure = failureAt(log, k, what);
    } else {
      result.failure = RunFailure{what, k, x0.t, std::string()};
    }
  };
  try {
    // The IMU's initial state from the base's, with row 0's rate (w_B = R_BI w_I).
    InitialState start;
    start.x = moved && !log.rows.empty()
                  ? imuFromBase(extrinsic, x0, extrinsic.q_BI * log.rows.front().gyro)
                  : x0;
    if (gyro_bias) {
      start.b_g = *gyro_bias;
      estimator.initialise(start);
    } else {
      estimator.reset(start.x);
    }
  } catch (const std::exception& e) {
    fail(std::string("reset threw: ") + e.what());
  } catch (...) {
    fail("reset threw an exception that is not a std::exception");
  }
  // The truth the NEES is scored against: the log's gt_v, or its pose differentiated (a pose-only
  // truth, as compare() does); a row without a valid truth gets NaN, left out of the ANEES.
  const TruthVelocity truth_v =
      log.layout.ground_truth ? truthVelocity(log, truth_velocity_window) : TruthVelocity{};
  result.given_contact.reserve(log.rows.size());
  for (; !result.failure && k < log.rows.size(); ++k) {
    const io::LogRow& row = log.rows[k];
    try {
      const double dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
      const StepInput& in = input_of(k, dt);
      std::array<bool, contact::kMaxFeet> given{};
      for (int i = 0; i < in.num_contacts; ++i) given[in.contacts[i].foot] = true;
      const auto t0 = std::chrono::steady_clock::now();
      estimator.step(in);
      busy += std::chrono::steady_clock::now() - t0;
      ++steps;
      const EstimateSample x_I = estimator.estimate();
      std::string unusable = unusableEstimate(x_I, nullptr);
      if (!unusable.empty()) {
        fail(unusable);
        break;
      }
      // Back to the base with the row's measured rate (bias not removed: the interface has none).
      const EstimateSample x = moved ? baseFromImu(extrinsic, x_I, row.gyro) : x_I;
      std::optional<BaseCovariance> cov = estimator.covariance();
      if (moved && cov) cov = baseCovarianceFromImu(extrinsic, x_I, row.gyro, *cov);
      unusable = unusableEstimate(x, cov ? &*cov : nullptr);
      if (!unusable.empty()) {
        fail(unusable);
        break;
      }
      double e = std::numeric_limits<double>::quiet_NaN();
      if (cov && log.layout.ground_truth && truth_v.available[k]) {
        const EstimateSample truth{row.t, row.gt_q, truth_v.v[k], row.gt_p};
        try {
          e = nees(truth, x, *cov);
        } catch (const std::invalid_argument&) {
          fail(std::string("covariance not symmetric positive definite") +
               (cov->has_attitude ? "" : " (velocity-position block)") + ": NEES undefined");
          break;
        }
      }
      result.trajectory.push_back(x);
      result.given_contact.push_back(given);
      after_row();
      if (!cov) continue;
      result.sigma.push_back(cov->P.diagonal().cwiseSqrt());
      result.nees_dof = neesDof(*cov);
      if (log.layout.ground_truth) result.nees.push_back(e);
    } catch (const std::exception& e) {
      fail(threwReason(e));
      break;
    } catch (...) {
      fail("threw an exception that is not a std::exception");
      break;
    }
  }
  result.health = estimator.health();
  result.stance_nis = estimator.stanceInnovations();
  result.us_per_step = steps == 0 ? 0.0 : busy.count() / static_cast<double>(steps);
  return result;
}

}  // namespace

std::optional<StillStart> stillStart(const io::Log& log,
                                     const engineering::StationaryInitParams& params) {
  engineering::StationaryInitialiser still(params);
  for (const io::LogRow& row : log.rows) {
    if (still.add(row.t, {row.gyro, row.acc})) break;
  }
  if (!still.ready()) return std::nullopt;  // gave up, or the log ended first
  const InitialState s = still.result();
  return StillStart{s.b_g, s.x.t};
}

std::string describeStart(const std::optional<StillStart>& still) {
  if (!still)
    return "no still window within initialisation.max_wait: every gyro bias starts at zero";
  std::ostringstream os;
  os << std::fixed << std::setprecision(5) << "gyro bias [" << still->b_g.x() << ", "
     << still->b_g.y() << ", " << still->b_g.z() << "] rad/s, the mean rate of the still window "
     << std::setprecision(2) << "ending at " << still->t_end << " s (initialisation.gyro_bias)";
  return os.str();
}

RunResult runOnLog(Estimator& estimator, const io::Log& log, const LogFrontend& frontend,
                   const EstimateSample& x0, double truth_velocity_window,
                   const std::optional<Eigen::Vector3d>& gyro_bias) {
  StepInput in;
  FootVelocityDifferentiator velocities;
  return runRows(
      estimator, log, frontend.extrinsic(), x0, gyro_bias, truth_velocity_window,
      [&](std::size_t k, double dt) -> const StepInput& {
        in = frontend.input(log.rows[k], dt, &velocities);
        return in;
      },
      [] {});
}

RunResult runOnLog(Estimator& estimator, const io::Log& log, ContactPipeline& pipeline,
                   const EstimateSample& x0, double truth_velocity_window,
                   const std::optional<Eigen::Vector3d>& gyro_bias) {
  pipeline.reset();
  std::chrono::duration<double, std::micro> busy{0};
  std::size_t steps = 0;
  std::vector<std::array<bool, contact::kMaxFeet>> detected;
  detected.reserve(log.rows.size());
  std::vector<SlipSummary> slip;
  slip.reserve(log.rows.size());
  std::array<bool, contact::kMaxFeet> stance{};  // of the row being run
  RunResult result = runRows(
      estimator, log, pipeline.frontend().extrinsic(), x0, gyro_bias, truth_velocity_window,
      [&](std::size_t k, double dt) -> const StepInput& {
        const auto t0 = std::chrono::steady_clock::now();
        const StepInput& in =
            pipeline.step(log.rows[k], dt, estimator.estimate(), estimator.covariance());
        busy += std::chrono::steady_clock::now() - t0;
        ++steps;
        const contact::ContactEstimate& c = pipeline.contacts();
        for (int foot = 0; foot < contact::kMaxFeet; ++foot) {
          stance[foot] = foot < c.num_feet && c.feet[foot].usable() && c.feet[foot].contact;
        }
        return in;
      },
      [&] {
        detected.push_back(stance);
        const slip::SlipReport& r = pipeline.slipReport();
        slip.push_back({r.num_feet, r.numSlipping(), r.all_slipping, r.outlier});
      });
  result.contact_source = pipeline.source();
  result.detected_contact = std::move(detected);
  result.slip = std::move(slip);
  result.slip_reaction = slip::slipReactionName(pipeline.options().slip);
  result.contact_diagnostics = pipeline.diagnostics();
  result.pipeline_us_per_step = steps == 0 ? 0.0 : busy.count() / static_cast<double>(steps);
  for (int f = 0; f < static_cast<int>(Fault::kCount); ++f) {
    result.health.count[f] += pipeline.health().count[f];
  }
  if (pipeline.health().total() > 0 &&
      (result.health.last_fault == Fault::kCount ||
       pipeline.health().last_fault_t >= result.health.last_fault_t)) {
    result.health.last_fault = pipeline.health().last_fault;
    result.health.last_fault_t = pipeline.health().last_fault_t;
  }
  return result;
}

std::string describe(const RunFailure& failure) {
  std::ostringstream os;
  if (!failure.where.empty()) os << failure.where << ", ";
  os << "t = " << failure.t << " s (row " << failure.row << "): " << failure.what;
  return os.str();
}

std::string describe(const Health& health) {
  std::string s;
  for (int f = 0; f < static_cast<int>(Fault::kCount); ++f) {
    const std::uint64_t n = health.count[static_cast<std::size_t>(f)];
    if (n == 0) continue;
    if (!s.empty()) s += ", ";
    s += std::to_string(n) + " " + faultName(static_cast<Fault>(f));
  }
  return s;
}

double normalisedAnees(const RunResult& run) {
  double sum = 0.0;
  std::size_t scored = 0;
  for (const double e : run.nees) {
    if (std::isnan(e)) continue;  // a row without a valid truth
    sum += e;
    ++scored;
  }
  if (scored == 0 || run.nees_dof == 0) return std::numeric_limits<double>::quiet_NaN();
  return sum / static_cast<double>(scored) / run.nees_dof;
}

EstimateSample initialState(const io::Log& log, double truth_velocity_window) {
  if (log.rows.empty()) throw std::invalid_argument("initialState: the log has no rows");
  const io::LogRow& first = log.rows.front();
  EstimateSample x0;
  x0.t = first.t;  // the run starts at row 0 whichever row the truth comes from
  // The first row whose truth is valid (a masked row may hold a zero quaternion).
  const auto valid = std::find_if(log.rows.begin(), log.rows.end(),
                                  [](const io::LogRow& row) { return row.gt_valid; });
  if (log.layout.ground_truth && valid != log.rows.end()) {
    x0.q = valid->gt_q;
    x0.p = valid->gt_p;
    // A pose-only truth: its velocity differentiated as the metrics do (eval/metrics.hpp).
    x0.v = log.layout.gt_velocity ? valid->gt_v
                                  : truthVelocity(log, truth_velocity_window)
                                        .v[static_cast<std::size_t>(valid - log.rows.begin())];
  } else {
    // At rest the accelerometer reads -R^T g: its direction is world up seen from the body. A
    // zero reading (free fall, a dead sensor) has no direction: level.
    if (first.acc.norm() > 0.0)
      x0.q = Eigen::Quaterniond::FromTwoVectors(first.acc.normalized(), Eigen::Vector3d::UnitZ());
  }
  return x0;
}

void runHartleyLog(Estimator& filter, const io::HartleyLog& log,
                   const std::function<void()>& after) {
  EstimateSample x0;
  x0.q = Eigen::Quaterniond(Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal().toDenseMatrix());
  filter.reset(x0);
  filter.step(StepInput{});  // the zero reading held before the log (t = 0, no feet)
  double t_previous = 0.0;
  for (const io::HartleySample& s : log.samples) {
    StepInput in;
    in.t = s.t;
    in.dt = s.t - t_previous;
    in.imu = s.imu;
    std::array<ContactMeasurement, io::kHartleyMaxFeet> stance;
    in.num_contacts = io::stanceFeet(s, stance);
    std::copy(stance.begin(), stance.begin() + in.num_contacts, in.contacts.begin());
    filter.step(in);
    if (after) after();
    t_previous = s.t;
  }
}

}  // namespace legkit::eval
