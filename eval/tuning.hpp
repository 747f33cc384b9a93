// `legkit tune`: the noise settings that matter, fitted to a recorded log (issue 22 item 3).
//
// The log is cut in two at fit_share of its rows: the parameters are fitted on the first part and
// the result is reported on the second, which the fit never saw (each part run from its own first
// row's truth, so that neither inherits the other's drift). What is fitted, in this order:
//  - the IMU's white-noise densities, on a log scale by golden-section search from the floor the
//    sensor shows at rest: the first still window (the stationary initialiser's test,
//    estimation/engineering/stationary_init.hpp: duration seconds whose block means do not move),
//    the largest axis' sample standard deviation times sqrt(dt). The floor alone is no setting:
//    on the iCub log it is 7.2e-4 rad/s/sqrt(Hz) where walking wants the paper's 0.01 (a filter
//    run on it was over-confident, ANEES 7.8, on the part the fit never saw). A log of seconds
//    shows no bias random walk (Allan's tau of hundreds of seconds): those stay, `legkit allan`
//    on a long resting record measures them;
//  - feet.stance_density (the stance foot's slip allowance) and frontend.foot_point_sigma (the
//    contact point's uncertainty), the same way; the four one after the other, `rounds` times;
//  - contact.settle_time (touchdown settling), over 0, 20, 40, 80 ms.
// With truth the search sees the first two thirds of the fitted part; the last third then scores
// the values given against the fitted ones, and the fitted ones are kept only if they score
// better there (on the iCub log's 6 s fitted part, with 3 touchdowns, they do not).
// The score of a candidate, on a log with truth, is the Gaussian negative log-likelihood of the
// truth under the filter's estimate, mean over the rows of NEES_k + sum_i log sigma_k,i^2
// (sigma: the square roots of the diagonal of P; the diagonal's log-determinant bounds log det P
// from above, Hadamard's inequality). It rewards a covariance as small as the errors allow and no
// smaller: a search on RMSE alone would shrink nothing and trust everything. On a log without
// truth, only the stance-foot innovations speak (Estimator::stanceInnovations()): the contact
// point's noise frontend.foot_point_sigma is the one at which their mean NIS per dimension is 1
// (bisection on the log scale: NIS falls as it grows), and nothing else is fitted.
// Derivative-free, not Ceres: each score is a whole filter run with discrete contact decisions in
// it, piecewise constant at the scale of finite differences, and there are three parameters.
// A parameter the log cannot fit keeps its value, with the reason: no still window; no stance foot
// or too few touchdowns in the fitted part; a score that moves by less than 1 % over the whole
// range (the log does not constrain it).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "estimation/contact/detectors.hpp"
#include "estimation/settings.hpp"
#include "io/log.hpp"

namespace legkit::eval {

struct TuneOptions {
  std::string estimator = "eskf";  // the filter whose score is fitted
  double fit_share = 0.5;          // the first part of the rows fitted, the rest reported (0, 1)
  int rounds = 2;                  // rounds of the search over the continuous parameters
};

// One setting: its value before and after, and whether (and why not) it was fitted.
struct TunedParameter {
  std::string key;  // as in the settings file, e.g. "feet.stance_density"
  double before = 0.0, after = 0.0;
  bool fitted = false;
  std::string how;  // how it was fitted, or why it was not
};

// One estimator on the part the fit never saw, with the settings given and the tuned ones.
struct HeldOutScore {
  std::string estimator;
  double position_rmse_before = 0.0, position_rmse_after = 0.0;  // [m]
  double anees_before = 0.0, anees_after = 0.0;                  // [-], 1: consistent
  double nis_before = 0.0, nis_after = 0.0;  // stance-foot NIS per dimension (NaN: none)
};

struct TuneReport {
  Settings settings;  // the settings given, with the fitted values
  std::vector<TunedParameter> parameters;
  std::vector<HeldOutScore> held_out;  // every estimator of the settings
  bool with_truth = false;             // scored on the truth (else on the innovations)
  // The IMU's white-noise floor at rest (gyro, accel), from the first still window; 0: none.
  double gyro_floor = 0.0, accel_floor = 0.0;
  double split_t = 0.0;  // the first time of the part the fit never saw [s]
  std::size_t fit_rows = 0, held_out_rows = 0;
};

// The rows [begin, end) of a log, with its layout, comments and source.
io::Log sliceLog(const io::Log& log, std::size_t begin, std::size_t end);

// Fits and reports as the file comment says. `context` gives the detectors' gait and logistic
// model (eval::runWithSettings). Throws std::invalid_argument for fit_share outside (0, 1),
// rounds < 1, an unknown estimator, or a log too short to cut (fewer than 200 rows a part).
TuneReport tune(const io::Log& log, const Settings& settings,
                const contact::DetectorContext& context, const TuneOptions& options = {});

}  // namespace legkit::eval
