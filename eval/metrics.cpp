#include "eval/metrics.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace legkit::eval {

double tiltError(const Eigen::Matrix3d& R_hat, const Eigen::Matrix3d& R) {
  const Eigen::Vector3d a = R_hat.transpose().col(2);  // world z seen from the estimated body
  const Eigen::Vector3d b = R.transpose().col(2);      // and from the true body
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

double yawError(const Eigen::Matrix3d& R_hat, const Eigen::Matrix3d& R) {
  const double d = std::atan2(R_hat(1, 0), R_hat(0, 0)) - std::atan2(R(1, 0), R(0, 0));
  return std::remainder(d, 2.0 * M_PI);  // wrap to [-pi, pi]
}

namespace {

struct Pose {
  Eigen::Matrix3d R;
  Eigen::Vector3d p;
  Pose operator*(const Pose& o) const { return {R * o.R, R * o.p + p}; }
  Pose inverse() const { return {R.transpose(), -(R.transpose() * p)}; }
};

Pose truePose(const io::LogRow& row) {
  return {row.gt_q.toRotationMatrix(), row.gt_p};
}
Pose estimatedPose(const EstimateSample& e) {
  return {e.q.toRotationMatrix(), e.p};
}

// Rows whose truth is scored: all of them, unless the log has a gt_valid column.
std::vector<std::size_t> validRows(const io::Log& truth) {
  std::vector<std::size_t> rows;
  rows.reserve(truth.rows.size());
  for (std::size_t k = 0; k < truth.rows.size(); ++k) {
    if (!truth.layout.gt_valid || truth.rows[k].gt_valid) rows.push_back(k);
  }
  return rows;
}

// ATE over the valid rows, aligned on the first of them.
double ateRmse(const io::Log& truth, const Trajectory& estimate,
               const std::vector<std::size_t>& valid) {
  const std::size_t k0 = valid.front();
  const Pose T_a = truePose(truth.rows[k0]) * estimatedPose(estimate[k0]).inverse();
  double s = 0.0;
  for (const std::size_t k : valid) {
    s += (truth.rows[k].gt_p - (T_a * estimatedPose(estimate[k])).p).squaredNorm();
  }
  return std::sqrt(s / static_cast<double>(valid.size()));
}

// The true positions of the valid rows and the estimated ones, a column per row.
struct Positions {
  Eigen::Matrix3Xd p;
  Eigen::Matrix3Xd p_hat;
};

Positions validPositions(const io::Log& truth, const Trajectory& estimate,
                         const std::vector<std::size_t>& valid) {
  Positions s{Eigen::Matrix3Xd(3, valid.size()), Eigen::Matrix3Xd(3, valid.size())};
  for (std::size_t i = 0; i < valid.size(); ++i) {
    s.p.col(static_cast<Eigen::Index>(i)) = truth.rows[valid[i]].gt_p;
    s.p_hat.col(static_cast<Eigen::Index>(i)) = estimate[valid[i]].p;
  }
  return s;
}

// The least-squares alignments need this many valid rows (fewer: not computed).
constexpr std::size_t kMinAlignedRows = 3;

// sqrt(mean_k |p_k - (R p_hat_k + t)|^2).
double alignedRmse(const Positions& s, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  return std::sqrt((s.p - ((R * s.p_hat).colwise() + t)).colwise().squaredNorm().mean());
}

// ATE after the rigid transform fitting p_hat to p in least squares (Umeyama 1991, no scale).
double ateSe3Rmse(const Positions& s) {
  const Eigen::Matrix4d T = Eigen::umeyama(s.p_hat, s.p, false);
  return alignedRmse(s, T.topLeftCorner<3, 3>(), T.topRightCorner<3, 1>());
}

// ATE after the yaw and translation fitting p_hat to p in least squares: on centred coordinates
// psi = atan2(sum x_hat y - y_hat x, sum x_hat x + y_hat y), t = c - R_z(psi) c_hat.
double ate4DofRmse(const Positions& s) {
  const Eigen::Vector3d c = s.p.rowwise().mean();
  const Eigen::Vector3d c_hat = s.p_hat.rowwise().mean();
  const Eigen::Matrix3Xd q = s.p.colwise() - c;
  const Eigen::Matrix3Xd q_hat = s.p_hat.colwise() - c_hat;
  const double psi =
      std::atan2((q_hat.row(0).cwiseProduct(q.row(1)) - q_hat.row(1).cwiseProduct(q.row(0))).sum(),
                 (q_hat.row(0).cwiseProduct(q.row(0)) + q_hat.row(1).cwiseProduct(q.row(1))).sum());
  const Eigen::Matrix3d R = Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return alignedRmse(s, R, c - R * c_hat);
}

// RPE over pairs of valid rows; travelled[k] is the truth's distance to valid row k.
RelativeError rpe(const io::Log& truth, const Trajectory& estimate,
                  const std::vector<std::size_t>& valid, const std::vector<double>& travelled,
                  double d) {
  RelativeError r;
  r.distance = d;
  double st = 0.0, sr = 0.0;
  std::size_t b = 0;  // index into valid of j
  for (std::size_t a = 0; a < valid.size(); ++a) {
    const std::size_t i = valid[a];
    b = std::max(b, a);
    while (b < valid.size() && travelled[valid[b]] - travelled[i] < d) ++b;
    if (b == valid.size()) break;
    const std::size_t j = valid[b];
    const Pose motion = truePose(truth.rows[i]).inverse() * truePose(truth.rows[j]);
    const Pose motion_hat = estimatedPose(estimate[i]).inverse() * estimatedPose(estimate[j]);
    const Pose E = motion.inverse() * motion_hat;
    st += E.p.squaredNorm();
    sr += std::pow(Eigen::AngleAxisd(E.R).angle(), 2);
    ++r.pairs;
  }
  r.computed = r.pairs > 0;
  if (r.computed) {
    r.translation_rmse = std::sqrt(st / r.pairs);
    r.translation_percent = 100.0 * r.translation_rmse / d;
    r.rotation_rmse_deg = std::sqrt(sr / r.pairs) * 180.0 / M_PI;
  }
  return r;
}

std::string numberText(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

}  // namespace

TruthVelocity truthVelocity(const io::Log& truth, double window) {
  if (!(window > 0.0)) {
    throw std::invalid_argument("eval::truthVelocity: the window must be > 0 s, got " +
                                numberText(window));
  }
  const std::size_t n = truth.rows.size();
  TruthVelocity out;
  out.v.assign(n, Eigen::Vector3d::Zero());
  out.available.assign(n, false);
  const std::vector<std::size_t> valid = validRows(truth);
  if (truth.layout.gt_velocity) {
    out.method = "the log's gt_vx..gt_vz";
    for (const std::size_t k : valid) {
      out.v[k] = truth.rows[k].gt_v;
      out.available[k] = true;
    }
    return out;
  }
  out.differentiated = true;
  out.method = "central difference of gt_p over a " + numberText(window) +
               " s window, valid rows only (the log has no gt_vx..gt_vz)";
  // v_k = (p_b - p_a) / (t_b - t_a), a and b the valid rows farthest from k in [t_k - w/2,
  // t_k + w/2]: both move forward with k, so one pass.
  std::size_t a = 0, b = 0;
  for (std::size_t m = 0; m < valid.size(); ++m) {
    const double t = truth.rows[valid[m]].t;
    while (truth.rows[valid[a]].t < t - 0.5 * window) ++a;
    b = std::max(b, m);
    while (b + 1 < valid.size() && truth.rows[valid[b + 1]].t <= t + 0.5 * window) ++b;
    if (a == b) continue;  // no other valid row within the window
    const io::LogRow& first = truth.rows[valid[a]];
    const io::LogRow& last = truth.rows[valid[b]];
    out.v[valid[m]] = (last.gt_p - first.gt_p) / (last.t - first.t);
    out.available[valid[m]] = true;
  }
  return out;
}

Metrics compare(const io::Log& truth, const Trajectory& estimate,
                const std::vector<double>& rpe_distances, const TruthOptions& options) {
  if (!truth.layout.ground_truth) {
    throw std::invalid_argument("eval::compare: the log has no ground-truth columns (gt_*)");
  }
  if (truth.rows.size() != estimate.size() || estimate.empty()) {
    std::ostringstream os;
    os << "eval::compare: " << estimate.size() << " estimates for " << truth.rows.size()
       << " log rows";
    throw std::invalid_argument(os.str());
  }
  if (!(options.distance_step >= 0.0) || !std::isfinite(options.distance_step)) {
    throw std::invalid_argument("eval::compare: the distance step must be >= 0 m, got " +
                                numberText(options.distance_step));
  }
  for (std::size_t k = 0; k < estimate.size(); ++k) {
    if (truth.rows[k].t != estimate[k].t) {
      std::ostringstream os;
      os << "eval::compare: estimate " << k << " is at t = " << estimate[k].t << " but log row "
         << k << " is at t = " << truth.rows[k].t;
      throw std::invalid_argument(os.str());
    }
  }
  const std::vector<std::size_t> valid = validRows(truth);
  const TruthVelocity velocity = truthVelocity(truth, options.velocity_window);
  Metrics m;
  m.scored_rows = static_cast<int>(valid.size());
  m.masked_rows = static_cast<int>(truth.rows.size() - valid.size());
  m.velocity_differentiated = velocity.differentiated;
  m.velocity_method = velocity.method;
  if (valid.empty()) {  // nothing to score: every metric "not computed"
    m.position_rmse = m.velocity_rmse = m.final_position_error = m.drift_percent = kNotComputed;
    m.tilt_rmse_deg = m.yaw_rmse_deg = m.ate_rmse = m.ate_se3_rmse = m.ate_4dof_rmse = kNotComputed;
    for (const double d : rpe_distances) m.rpe.push_back(RelativeError{d});
    return m;
  }
  double sp = 0.0, sv = 0.0, st = 0.0, sy = 0.0;
  std::vector<double> travelled(estimate.size(), 0.0);      // distance along the truth to row k
  Eigen::Vector3d anchor = truth.rows[valid.front()].gt_p;  // the truth resampled every d_min
  for (const std::size_t k : valid) {
    const io::LogRow& row = truth.rows[k];
    const EstimateSample& e = estimate[k];
    const Eigen::Matrix3d R = row.gt_q.toRotationMatrix();
    const Eigen::Matrix3d R_hat = e.q.toRotationMatrix();
    sp += (e.p - row.gt_p).squaredNorm();
    if (velocity.available[k]) {
      sv += (e.v - velocity.v[k]).squaredNorm();
      ++m.velocity_rows;
    }
    st += std::pow(tiltError(R_hat, R), 2);
    sy += std::pow(yawError(R_hat, R), 2);
    const double step = (row.gt_p - anchor).norm();
    if (step > 0.0 && step >= options.distance_step) {
      m.distance += step;
      anchor = row.gt_p;
    }
    travelled[k] = m.distance;
  }
  const double n = static_cast<double>(valid.size());
  const double deg = 180.0 / M_PI;
  m.position_rmse = std::sqrt(sp / n);
  m.velocity_rmse = m.velocity_rows > 0 ? std::sqrt(sv / m.velocity_rows) : kNotComputed;
  m.tilt_rmse_deg = std::sqrt(st / n) * deg;
  m.yaw_rmse_deg = std::sqrt(sy / n) * deg;
  m.final_position_error = (estimate[valid.back()].p - truth.rows[valid.back()].gt_p).norm();
  m.drift_percent = m.distance > 0.0 ? 100.0 * m.final_position_error / m.distance : kNotComputed;
  m.ate_rmse = ateRmse(truth, estimate, valid);
  const Positions positions = validPositions(truth, estimate, valid);
  const bool aligned = valid.size() >= kMinAlignedRows;
  m.ate_se3_rmse = aligned ? ateSe3Rmse(positions) : kNotComputed;
  m.ate_4dof_rmse = aligned ? ate4DofRmse(positions) : kNotComputed;
  for (const double d : rpe_distances) m.rpe.push_back(rpe(truth, estimate, valid, travelled, d));
  return m;
}

}  // namespace legkit::eval
