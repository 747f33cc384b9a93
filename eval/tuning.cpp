#include "eval/tuning.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "estimation/engineering/stationary_init.hpp"
#include "estimation/estimators.hpp"
#include "eval/log_run.hpp"
#include "eval/metrics.hpp"

namespace legkit::eval {
namespace {

constexpr std::size_t kMinPartRows = 200;
// Fewer touchdowns than this in the fitted part say nothing about settling.
constexpr int kMinTouchdowns = 10;
// A parameter whose best and worst score differ by less than this per row and degree of freedom
// [nats] is not constrained by the log: 0.01 is a 1 % change of a consistent filter's NEES.
constexpr double kFlatScore = 0.01;
constexpr double kSettleCandidates[] = {0.0, 0.02, 0.04, 0.08};  // [s]
constexpr int kGoldenIterations = 14;  // 0.618^14 of the range: 0.01 decade of 3.5
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string format(double x) {
  std::ostringstream os;
  os.precision(3);
  os << x;
  return os.str();
}

// The mean over the rows with a NEES of NEES_k + sum_i log sigma_k,i^2 over the NEES's degrees
// of freedom, per degree of freedom; +inf for a run that failed or has none.
double negativeLogLikelihood(const RunResult& run) {
  if (run.failed() || run.nees_dof == 0) return kInf;
  const int first = run.nees_dof == 9 ? 0 : 3;  // sigma is (theta, v, p); 6 dof: no attitude
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < run.nees.size(); ++k) {
    if (!std::isfinite(run.nees[k])) continue;
    double log_det = 0.0;
    for (int i = first; i < 9; ++i) log_det += 2.0 * std::log(run.sigma[k](i));
    sum += run.nees[k] + log_det;
    ++n;
  }
  return n > 0 ? sum / static_cast<double>(n) / run.nees_dof : kInf;
}

double nisPerDimension(const RunResult& run) {
  return run.stance_nis ? run.stance_nis->meanPerDimension() : kNaN;
}

// Touchdowns and stance samples the estimator was given over a run.
std::pair<int, long> stanceCounts(const RunResult& run) {
  int touchdowns = 0;
  long stance = 0;
  for (std::size_t k = 0; k < run.given_contact.size(); ++k) {
    for (std::size_t f = 0; f < run.given_contact[k].size(); ++f) {
      stance += run.given_contact[k][f];
      touchdowns += k > 0 && run.given_contact[k][f] && !run.given_contact[k - 1][f];
    }
  }
  return {touchdowns, stance};
}

struct Found {
  double x = 0.0, score = kInf;
  double worst = -kInf;  // the worst finite score seen
};

// Golden-section search of `score` over log10 x in [lo, hi] (both ends scored too).
Found goldenSearch(const std::function<double(double)>& score, double lo, double hi) {
  Found found;
  const auto at = [&](double log_x) {
    const double x = std::pow(10.0, log_x);
    const double s = score(x);
    if (s < found.score) found = {x, s, found.worst};
    if (std::isfinite(s)) found.worst = std::max(found.worst, s);
    return s;
  };
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = std::log10(lo), b = std::log10(hi);
  at(a);
  at(b);
  double c = b - r * (b - a), d = a + r * (b - a);
  double fc = at(c), fd = at(d);
  for (int i = 0; i < kGoldenIterations; ++i) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - r * (b - a);
      fc = at(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + r * (b - a);
      fd = at(d);
    }
  }
  return found;
}

// The white-noise densities the sensor shows standing still: the first still window of the
// fitted part (see tuning.hpp), a held sample (equal to the one before: an IMU slower than the
// log) counted once. Nothing, and why in `why_not`, without a usable window.
struct ImuFloor {
  double gyro = 0.0, accel = 0.0;  // [rad/s/sqrt(Hz)], [m/s^2/sqrt(Hz)]
  std::string where;               // "the still window t0 - t1 s (n samples)"
};
std::optional<ImuFloor> stillFloor(const io::Log& part, const Settings& s, std::string& why_not) {
  engineering::StationaryInitParams p = s.initialisation;
  p.enabled = true;
  p.max_wait = part.rows.back().t - part.rows.front().t + 1.0;
  engineering::StationaryInitialiser still(p);
  for (const io::LogRow& row : part.rows) {
    if (still.add(row.t, {row.gyro, row.acc})) break;
  }
  if (!still.ready()) {
    why_not = "no still window of " + format(p.duration) + " s in the fitted part";
    return std::nullopt;
  }
  const double t1 = still.result().x.t, t0 = t1 - p.duration;
  Eigen::Matrix<double, 6, 1> sum = Eigen::Matrix<double, 6, 1>::Zero(), sq = sum;
  int n = 0;
  const io::LogRow* previous = nullptr;
  for (const io::LogRow& row : part.rows) {
    if (row.t < t0 || row.t > t1) continue;
    if (previous && row.gyro == previous->gyro && row.acc == previous->acc) continue;
    previous = &row;
    Eigen::Matrix<double, 6, 1> x;
    x << row.gyro, row.acc;
    sum += x;
    sq += x.cwiseProduct(x);
    ++n;
  }
  const double dt = p.duration / std::max(n - 1, 1);
  const Eigen::Matrix<double, 6, 1> mean = sum / std::max(n, 1);
  const Eigen::Matrix<double, 6, 1> var =
      (sq / std::max(n, 1) - mean.cwiseProduct(mean)).cwiseMax(0.0);
  // The largest axis: a density the filter uses on every axis must not be below any of them.
  ImuFloor f{var.head<3>().cwiseSqrt().maxCoeff() * std::sqrt(dt),
             var.tail<3>().cwiseSqrt().maxCoeff() * std::sqrt(dt),
             "the still window " + format(t0) + " - " + format(t1) + " s (" + std::to_string(n) +
                 " samples)"};
  if (n < 20 || !(f.gyro > 0.0 && f.accel > 0.0)) {
    why_not = "the still window has " + std::to_string(n) +
              " distinct samples or a sensor that never changes";
    return std::nullopt;
  }
  return f;
}

}  // namespace

io::Log sliceLog(const io::Log& log, std::size_t begin, std::size_t end) {
  io::Log part;
  part.layout = log.layout;
  part.comments = log.comments;
  part.source = log.source;
  part.rows.assign(log.rows.begin() + static_cast<std::ptrdiff_t>(begin),
                   log.rows.begin() + static_cast<std::ptrdiff_t>(end));
  return part;
}

TuneReport tune(const io::Log& log, const Settings& settings,
                const contact::DetectorContext& context, const TuneOptions& o) {
  if (!(o.fit_share > 0.0 && o.fit_share < 1.0)) {
    throw std::invalid_argument("tune: the fitted share must be in (0, 1), got " +
                                format(o.fit_share));
  }
  if (o.rounds < 1) throw std::invalid_argument("tune: rounds must be at least 1");
  const std::vector<std::string> known = estimatorNames();
  if (std::find(known.begin(), known.end(), o.estimator) == known.end()) {
    throw std::invalid_argument("tune: unknown estimator '" + o.estimator + "'");
  }
  const auto split = static_cast<std::size_t>(o.fit_share * static_cast<double>(log.rows.size()));
  if (split < kMinPartRows || log.rows.size() - split < kMinPartRows) {
    throw std::invalid_argument("tune: " + std::to_string(log.rows.size()) + " rows cut at " +
                                format(o.fit_share) +
                                " leave a part of fewer "
                                "than " +
                                std::to_string(kMinPartRows) + " rows");
  }
  const io::Log fit = sliceLog(log, 0, split);
  const io::Log held = sliceLog(log, split, log.rows.size());

  TuneReport report;
  report.settings = settings;
  report.with_truth = log.layout.ground_truth;
  report.split_t = held.rows.front().t;
  report.fit_rows = fit.rows.size();
  report.held_out_rows = held.rows.size();
  Settings& s = report.settings;
  std::vector<TunedParameter>& out = report.parameters;

  std::string no_floor;
  const std::optional<ImuFloor> floor = stillFloor(fit, s, no_floor);
  if (floor) report.gyro_floor = floor->gyro, report.accel_floor = floor->accel;
  TunedParameter gyro{
      "imu.gyro_noise_density", s.imu.gyro_noise_density, s.imu.gyro_noise_density, false, {}};
  TunedParameter accel{
      "imu.accel_noise_density", s.imu.accel_noise_density, s.imu.accel_noise_density, false, {}};

  // With truth the search sees the first two thirds of the fitted part, and the last third
  // decides whether its result is kept at all (a few seconds of a slow walk fit noise that the
  // next few do not show; the iCub log's first six seconds did).
  const std::size_t search_end = report.with_truth ? split * 2 / 3 : split;
  const io::Log search = sliceLog(log, 0, search_end);
  const auto runFit = [&](const Settings& candidate) {
    return runWithSettings(search, candidate, o.estimator, context);
  };
  const RunResult first = runFit(s);
  const auto [touchdowns, stance] = stanceCounts(first);

  TunedParameter density{
      "feet.stance_density", s.feet.stance_density, s.feet.stance_density, false, {}};
  TunedParameter point{"frontend.foot_point_sigma",
                       s.frontend.foot_point_sigma,
                       s.frontend.foot_point_sigma,
                       false,
                       {}};
  TunedParameter settle{
      "contact.settle_time", s.pipeline.settle_time, s.pipeline.settle_time, false, {}};
  // The IMU densities' search range: from the still window's floor (or a tenth of the value
  // given) to a hundred times it, the value given always inside.
  const auto range = [](double given, std::optional<double> lowest) {
    const double lo = lowest ? std::min(*lowest, given) : given / 10.0;
    return std::pair{lo, std::max(100.0 * lo, 10.0 * given)};
  };
  const auto [gyro_lo, gyro_hi] =
      range(s.imu.gyro_noise_density, floor ? std::optional(floor->gyro) : std::nullopt);
  const auto [accel_lo, accel_hi] =
      range(s.imu.accel_noise_density, floor ? std::optional(floor->accel) : std::nullopt);
  const std::string floor_text = floor ? "from " + format(floor->gyro) + " / " +
                                             format(floor->accel) + ", the floor of " + floor->where
                                       : "no floor: " + no_floor;
  if (!report.with_truth) {
    gyro.how = accel.how =
        "kept: " +
        (floor ? "the sensor's floor at rest is " + format(floor->gyro) + " / " +
                     format(floor->accel) + " (" + floor->where +
                     "), a filter in motion needs more, and without truth nothing says how much"
               : no_floor);
  }
  if (stance == 0) {
    density.how = point.how = settle.how = "kept: no stance foot in the fitted part";
    if (report.with_truth) gyro.how = accel.how = "kept: no stance foot in the fitted part";
  } else if (report.with_truth) {
    // Each continuous parameter in turn, the others held, o.rounds times round.
    struct Knob {
      TunedParameter* parameter;
      double& (*value)(Settings&);
      double lo, hi;  // the search range
    };
    const Knob knobs[] = {
        {&gyro, [](Settings& c) -> double& { return c.imu.gyro_noise_density; }, gyro_lo, gyro_hi},
        {&accel, [](Settings& c) -> double& { return c.imu.accel_noise_density; }, accel_lo,
         accel_hi},
        {&density, [](Settings& c) -> double& { return c.feet.stance_density; }, 1e-4, 0.3},
        {&point, [](Settings& c) -> double& { return c.frontend.foot_point_sigma; }, 1e-4, 0.05}};
    for (int round = 0; round < o.rounds; ++round) {
      for (const Knob& k : knobs) {
        const Found f = goldenSearch(
            [&](double x) {
              Settings c = s;
              k.value(c) = x;
              return negativeLogLikelihood(runFit(c));
            },
            k.lo, k.hi);
        const bool flat = !(f.worst - f.score > kFlatScore);
        if (std::isfinite(f.score) && !flat) {
          k.value(s) = k.parameter->after = f.x;
          k.parameter->fitted = true;
          k.parameter->how =
              "golden-section search over " + format(k.lo) + " - " + format(k.hi) +
              " on the truth's log-likelihood (" + format(f.score) + " per row and dof)" +
              (k.parameter == &gyro || k.parameter == &accel ? ", " + floor_text : "");
        } else if (!k.parameter->fitted) {
          k.parameter->how = std::isfinite(f.score)
                                 ? "kept: the log does not constrain it (the score moves by " +
                                       format(f.worst - f.score) + " over the range)"
                                 : "kept: every candidate's run failed";
        }
      }
    }
    if (touchdowns < kMinTouchdowns) {
      settle.how = "kept: " + std::to_string(touchdowns) + " touchdowns in the fitted part (" +
                   std::to_string(kMinTouchdowns) + " needed)";
    } else {
      double best = kInf, worst = -kInf, best_t = s.pipeline.settle_time;
      for (const double t : kSettleCandidates) {
        Settings c = s;
        c.pipeline.settle_time = t;
        const double score = negativeLogLikelihood(runFit(c));
        if (score < best) best = score, best_t = t;
        if (std::isfinite(score)) worst = std::max(worst, score);
      }
      if (std::isfinite(best) && worst - best > kFlatScore) {
        s.pipeline.settle_time = settle.after = best_t;
        settle.fitted = true;
        settle.how = "the best of 0, 20, 40, 80 ms on the truth's log-likelihood";
      } else {
        settle.how = "kept: the log does not constrain it";
      }
    }
  } else {
    // Without truth: the contact point's white noise whose stance-foot NIS per dimension is 1.
    // It is what the windowed NIS answers to (innovation_windows.hpp); the stance density moves
    // it little (the analytic trot with a 1 um foot point: 6.0 at 1e-4, 1.5 at 0.3).
    const auto nisAt = [&](double x) {
      Settings c = s;
      c.frontend.foot_point_sigma = x;
      return nisPerDimension(runFit(c));
    };
    constexpr double kLo = 1e-5, kHi = 0.05;  // [m]
    double lo = std::log10(kLo), hi = std::log10(kHi);
    const double nis_lo = nisAt(kLo), nis_hi = nisAt(kHi);
    if (!std::isfinite(nis_lo) || !std::isfinite(nis_hi)) {
      point.how = "kept: the " + o.estimator + " counts no stance-foot innovations";
    } else if (nis_hi > 1.0 || nis_lo < 1.0) {
      point.how = "kept: the NIS per dimension is " + format(nis_lo) + " at " + format(kLo) +
                  " m and " + format(nis_hi) + " at " + format(kHi) +
                  " m, never 1 (another noise is off: the encoders', the IMU's?)";
    } else {
      for (int i = 0; i < kGoldenIterations; ++i) {
        const double mid = 0.5 * (lo + hi);
        (nisAt(std::pow(10.0, mid)) > 1.0 ? lo : hi) = mid;
      }
      s.frontend.foot_point_sigma = point.after = std::pow(10.0, 0.5 * (lo + hi));
      point.fitted = true;
      point.how = "bisection to a stance-foot NIS of 1 per dimension (no truth)";
    }
    density.how = "kept: without truth the innovations cannot tell it from the foot point's noise";
    settle.how = "kept: without truth nothing scores settling";
  }
  if (report.with_truth) {
    const io::Log check = sliceLog(log, search_end, split);
    const auto validation = [&](const Settings& c) {
      return negativeLogLikelihood(runWithSettings(check, c, o.estimator, context));
    };
    const double given = validation(settings), tuned = validation(s);
    if (!(tuned < given)) {
      for (TunedParameter* p : {&gyro, &accel, &density, &point, &settle}) {
        if (!p->fitted) continue;
        p->how = "kept: fitted " + format(p->after) +
                 ", but the last third of the fitted part "
                 "scored the values given better (" +
                 format(given) + " against " + format(tuned) + " per row and dof)";
        p->after = p->before;
        p->fitted = false;
      }
      s = settings;
    }
  }
  out.push_back(gyro);
  out.push_back(accel);
  const std::string no_walk =
      "kept: seconds of a log show no bias random walk (legkit allan on a long resting record "
      "measures it)";
  out.push_back({"imu.gyro_bias_random_walk", s.imu.gyro_bias_random_walk,
                 s.imu.gyro_bias_random_walk, false, no_walk});
  out.push_back({"imu.accel_bias_random_walk", s.imu.accel_bias_random_walk,
                 s.imu.accel_bias_random_walk, false, no_walk});
  out.push_back(density);
  out.push_back(point);
  out.push_back(settle);

  // The part the fit never saw, every estimator, before and after.
  const std::vector<std::string> names = settings.estimators.empty() ? known : settings.estimators;
  for (const std::string& name : names) {
    HeldOutScore h;
    h.estimator = name;
    for (const bool after : {false, true}) {
      const Settings& c = after ? s : settings;
      double rmse = kNaN, anees = kNaN, nis = kNaN;
      if (report.with_truth) {
        const RunResult r = runWithSettings(held, c, name, context);
        if (!r.failed()) {
          TruthOptions truth;
          truth.velocity_window = c.truth_velocity_window;
          rmse = compare(held, r.trajectory, {}, truth).position_rmse;
          anees = normalisedAnees(r);
          nis = nisPerDimension(r);
        }
      } else {
        // No truth to start the second part from: the whole log run, less its fitted part.
        const RunResult whole = runWithSettings(log, c, name, context);
        const RunResult part = runWithSettings(fit, c, name, context);
        if (whole.stance_nis && part.stance_nis &&
            whole.stance_nis->dimensions > part.stance_nis->dimensions) {
          nis = (whole.stance_nis->nis - part.stance_nis->nis) /
                static_cast<double>(whole.stance_nis->dimensions - part.stance_nis->dimensions);
        }
      }
      (after ? h.position_rmse_after : h.position_rmse_before) = rmse;
      (after ? h.anees_after : h.anees_before) = anees;
      (after ? h.nis_after : h.nis_before) = nis;
    }
    report.held_out.push_back(h);
  }
  return report;
}

}  // namespace legkit::eval
