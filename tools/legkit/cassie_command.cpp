#include "cassie_command.hpp"

#include <chrono>
#include <cstdlib>
#include <iomanip>

#include "eval/runner.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

// The log's default place: the copy of data/hartley-cassie/ that CMake unpacks into the build
// tree, unless LEGKIT_CASSIE_LOG says otherwise.
std::string defaultLog() {
  if (const char* env = std::getenv("LEGKIT_CASSIE_LOG")) return env;
  return LEGKIT_CASSIE_LOG_FILE;
}

}  // namespace

CassieCommand::CassieCommand(CLI::App& app)
    : command_(app.add_subcommand(
          "cassie", "Run the invariant EKF on the reference's Cassie log; print the final state")),
      file_(defaultLog()) {
  CLI::App& c = *command_;
  c.add_option("file", file_, "Log in the reference's text format (IMU/CONTACT/KINEMATIC lines)")
      ->check(nonEmptyName())
      ->capture_default_str();
  CLI::Option* exact =
      c.add_flag("--exact", exact_,
                 "Use the kit's exact closed-form Phi instead of the reference's first-order one");
  c.add_flag("--reference", reference_,
             "Place a foot that touches down with the attitude from before the correction, as "
             "the reference does: its own output, to rounding")
      ->excludes(exact);
}

int CassieCommand::run(std::ostream& out) const {
  const io::HartleyLog log = io::readHartleyLog(file_);
  invariant::InvariantEkfParams params = invariant::InvariantEkfParams::hartleyExample();
  if (exact_) params.discretisation = invariant::inekf::Discretisation::kExact;
  if (reference_) params.touchdown_attitude = invariant::inekf::TouchdownAttitude::kPredicted;
  invariant::InvariantEkf filter(params);
  const auto start = std::chrono::steady_clock::now();
  eval::runHartleyLog(filter, log);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const EstimateSample x = filter.estimate();
  const Eigen::IOFormat row(Eigen::StreamPrecision, Eigen::DontAlignCols, " ", "  ");
  out << std::setprecision(6);
  out << "invariant EKF on " << file_ << "\n"
      << log.samples.size() << " samples, " << (exact_ ? "exact" : "first-order")
      << " Phi, gyro 0.01, accel 0.1, bias 1e-5 / 1e-4, contact 0.01, P0 = I, touchdown "
      << (reference_ ? "with the predicted attitude (the reference's)"
                     : "with the corrected attitude (the kit's)")
      << "\n"
      << "final state at t = " << x.t << " s:\n"
      << "  R   = " << filter.X().R().format(row) << "\n"
      << "  v   = " << x.v.transpose().format(row) << " m/s\n"
      << "  p   = " << x.p.transpose().format(row) << " m\n"
      << "  b_g = " << filter.b_g().transpose().format(row) << " rad/s\n"
      << "  b_a = " << filter.b_a().transpose().format(row) << " m/s^2\n"
      << "  feet held: " << filter.numFeet() << "\n"
      << "  sigma (theta, v, p) = "
      << filter.covariance()->P.diagonal().cwiseSqrt().transpose().format(row) << "\n"
      << std::setprecision(3) << "  " << 1e6 * seconds / log.samples.size()
      << " us per step (reading excluded)\n";
  return 0;
}

}  // namespace legkit::tools
