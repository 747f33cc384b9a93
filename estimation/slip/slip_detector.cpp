#include "estimation/slip/slip_detector.hpp"

#include <cmath>
#include <lie/so3.hpp>
#include <limits>
#include <stdexcept>
#include <string>

#include "model/imu_model.hpp"

namespace legkit::slip {

namespace {

// F(x) of chi2_3: erf(sqrt(x/2)) - sqrt(2x/pi) exp(-x/2).
double chi2Cdf3(double x) {
  const double pi = 3.14159265358979323846;
  return std::erf(std::sqrt(x / 2.0)) - std::sqrt(2.0 * x / pi) * std::exp(-x / 2.0);
}

// r^T S^-1 r for a symmetric positive definite S, by the closed-form inverse (adjugate over the
// determinant, upper triangle read); +inf when a leading minor is not positive.
double mahalanobis2(const Eigen::Vector3d& r, const Eigen::Matrix3d& S) {
  const double a = S(0, 0), b = S(0, 1), c = S(0, 2), d = S(1, 1), e = S(1, 2), f = S(2, 2);
  const double A = d * f - e * e, B = c * e - b * f, C = b * e - c * d;  // first adjugate row
  const double minor2 = a * d - b * b, det = a * A + b * B + c * C;
  if (!(a > 0.0 && minor2 > 0.0 && det > 0.0)) return std::numeric_limits<double>::infinity();
  const double D = a * f - c * c, E = b * c - a * e;
  const double x = r(0), y = r(1), z = r(2);
  return (A * x * x + D * y * y + minor2 * z * z + 2.0 * (B * x * y + C * x * z + E * y * z)) / det;
}

void checkNonNegative(double value, const char* name) {
  if (!std::isfinite(value) || value < 0.0) {
    throw std::invalid_argument(std::string("SlipParams: ") + name +
                                " must be finite and >= 0, got " + std::to_string(value));
  }
}

}  // namespace

double chi2Quantile3(double alpha) {
  if (!(alpha > 0.0 && alpha < 1.0)) {
    throw std::invalid_argument("chi2Quantile3: alpha must be in (0, 1), got " +
                                std::to_string(alpha));
  }
  // F is increasing: bisection on [0, hi] with F(hi) > alpha, to double precision.
  double lo = 0.0, hi = 1.0;
  while (chi2Cdf3(hi) < alpha) hi *= 2.0;
  for (int k = 0; k < 200 && hi - lo > 1e-13 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (chi2Cdf3(mid) < alpha ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

bool SlipReport::slipping(int foot) const {
  for (int k = 0; k < num_feet; ++k) {
    if (feet[k].foot == foot) return feet[k].slipping;
  }
  return false;
}

int SlipReport::numSlipping() const {
  int n = 0;
  for (int k = 0; k < num_feet; ++k) n += feet[k].slipping ? 1 : 0;
  return n;
}

SlipDetector::SlipDetector(const SlipParams& params)
    : params_(params), threshold_(chi2Quantile3(params.alpha)) {
  checkNonNegative(params.gyro_sigma, "gyro_sigma");
  checkNonNegative(params.accel_sigma, "accel_sigma");
  checkNonNegative(params.accel_bias_sigma, "accel_bias_sigma");
  checkNonNegative(params.max_propagation, "max_propagation");
  if (!(params.foot_velocity_sigma > 0.0) || !std::isfinite(params.foot_velocity_sigma)) {
    throw std::invalid_argument("SlipParams: foot_velocity_sigma must be finite and > 0");
  }
  if (!(params.fallback_velocity_sigma > 0.0) || !std::isfinite(params.fallback_velocity_sigma)) {
    throw std::invalid_argument("SlipParams: fallback_velocity_sigma must be finite and > 0");
  }
  if (!(params.anchor_window > 0.0) || !(params.max_anchor_age >= params.anchor_window) ||
      !std::isfinite(params.max_anchor_age)) {
    throw std::invalid_argument(
        "SlipParams: anchor_window must be > 0 and max_anchor_age >= anchor_window, finite");
  }
  if (params.confirm_samples < 1) {
    throw std::invalid_argument("SlipParams: confirm_samples must be >= 1");
  }
  if (!(params.inflate >= 1.0) || !std::isfinite(params.inflate)) {
    throw std::invalid_argument("SlipParams: inflate must be finite and >= 1");
  }
  noise_.gyro_cov = Eigen::Matrix3d::Identity() * params.gyro_sigma * params.gyro_sigma;
  noise_.r_dot_cov =
      Eigen::Matrix3d::Identity() * params.foot_velocity_sigma * params.foot_velocity_sigma;
}

void SlipDetector::reset() {
  anchored_ = false;
  anchor_t_ = last_t_ = 0.0;
  exceeded_.fill(0);
  common_exceeded_ = 0;
  v_imu_.setZero();
  anchor_cov_.setZero();
  anchor_att_.setZero();
}

SlipReport SlipDetector::check(const StepInput& in, const EstimateSample& x) {
  BaseCovariance P;
  P.has_attitude = false;
  P.P.block<3, 3>(3, 3) = Eigen::Matrix3d::Identity() * params_.fallback_velocity_sigma *
                          params_.fallback_velocity_sigma;
  return check(in, x, P);
}

SlipReport SlipDetector::check(const StepInput& in, const EstimateSample& x,
                               const BaseCovariance& P) {
  SlipReport report;
  report.t = in.t;
  report.threshold = threshold_;
  const Eigen::Matrix3d R = x.q.normalized().toRotationMatrix();
  const Eigen::Vector3d& w_b = in.imu.w_m;
  const Eigen::Matrix3d w_x = lie::hat3(w_b);
  const Eigen::Matrix3d P_tt = P.P.block<3, 3>(0, 0), P_tv = P.P.block<3, 3>(0, 3),
                        P_vv = P.P.block<3, 3>(3, 3);

  // v_hat at the input's time: the estimate of x.t carried over the gap by the IMU.
  Eigen::Vector3d v_hat = x.v;
  const double gap = in.t - x.t;
  if (gap > 0.0 && gap <= params_.max_propagation) {
    v_hat += (R * in.imu.a_m + model::gravity()) * gap;
  }

  // Per foot: r_i, R_i (baseVelocityCovariance, inlined without its argument checks), S_i, d2_i.
  for (int k = 0; k < in.num_contacts; ++k) {
    const ContactMeasurement& c = in.contacts[k];
    if (!c.v_body) continue;
    FootSlip& f = report.feet[report.num_feet++];
    f.foot = c.foot;
    f.v_leg = -R * (w_b.cross(c.p_body) + *c.v_body);  // v_leg,i = -R (w_b x p_i + v_body,i)
    const Eigen::Matrix3d r_x = lie::hat3(c.p_body);
    f.R = R *
          (r_x * noise_.gyro_cov * r_x.transpose() + w_x * c.cov * w_x.transpose() +
           noise_.r_dot_cov) *
          R.transpose();
    f.residual = f.v_leg - v_hat;  // r_i = v_leg,i - v_hat
    if (P.has_attitude) {
      const Eigen::Matrix3d A = lie::hat3(f.v_leg);  // H_i's attitude block [v_leg,i]_x
      f.S = A * P_tt * A.transpose() + A * P_tv + P_tv.transpose() * A.transpose() + P_vv + f.R;
    } else {
      f.S = P_vv + f.R;
    }
    f.d2 = mahalanobis2(f.residual, f.S);
    f.exceeds = f.d2 > threshold_;
  }

  // Pairwise consistency: eps_ij = v_leg,i - v_leg,j against R_i + R_j.
  std::array<std::array<bool, kMaxFeet>, kMaxFeet> disagree{};
  for (int i = 0; i < report.num_feet; ++i) {
    for (int j = i + 1; j < report.num_feet; ++j) {
      const FootSlip &a = report.feet[i], &b = report.feet[j];
      const bool d = mahalanobis2(a.v_leg - b.v_leg, a.R + b.R) > threshold_;
      disagree[i][j] = disagree[j][i] = d;
      report.inconsistent_pairs += d ? 1 : 0;
    }
  }
  // The outlier: disagrees with every other foot while those all agree, among themselves and with
  // the filter (none of them exceeds its own test: two feet sliding together must not outvote the
  // one that holds). Needs >= 3 feet.
  if (report.num_feet >= 3) {
    for (int i = 0; i < report.num_feet; ++i) {
      const int others = report.num_feet - 1;
      int with_i = 0;
      bool others_pass = true;
      for (int j = 0; j < report.num_feet; ++j) {
        if (j == i) continue;
        with_i += disagree[i][j] ? 1 : 0;
        others_pass = others_pass && !report.feet[j].exceeds;
      }
      if (with_i == others && report.inconsistent_pairs - with_i == 0 && others_pass) {
        report.outlier = report.feet[i].foot;
        report.feet[i].exceeds = true;
        break;
      }
    }
  }
  // Confirmation: exceeded at confirm_samples consecutive checks (a foot not checked starts over).
  std::array<int, kMaxFeet> counts{};
  for (int k = 0; k < report.num_feet; ++k) {
    FootSlip& f = report.feet[k];
    if (f.foot < 0 || f.foot >= kMaxFeet) continue;  // StepInput's contract: ids in [0, 8)
    counts[f.foot] = f.exceeds ? exceeded_[f.foot] + 1 : 0;
    f.slipping = counts[f.foot] >= params_.confirm_samples;
  }
  exceeded_ = counts;
  report.all_slipping = report.num_feet > 0 && report.numSlipping() == report.num_feet;
  checkCommon(in, x, R, P, report);
  return report;
}

void SlipDetector::checkCommon(const StepInput& in, const EstimateSample& x,
                               const Eigen::Matrix3d& R, const BaseCovariance& P,
                               SlipReport& report) {
  const Eigen::Vector3d g = model::gravity();
  if (anchored_ && in.t > last_t_) {
    v_imu_ += (R * in.imu.a_m + g) * (in.t - last_t_);  // v_imu += (R a_m + g) dt
  }
  last_t_ = in.t;

  bool fired = false;
  const double T = in.t - anchor_t_;
  int exceeding = 0;
  for (int k = 0; k < report.num_feet; ++k) exceeding += report.feet[k].exceeds ? 1 : 0;
  if (anchored_ && report.num_feet > 0) {
    // The legs' common velocity: the mean over the feet that pass their own test (all if none).
    const bool use_all = exceeding == report.num_feet;
    Eigen::Vector3d v_c = Eigen::Vector3d::Zero();
    Eigen::Matrix3d cov_c = Eigen::Matrix3d::Zero();
    int m = 0;
    for (int k = 0; k < report.num_feet; ++k) {
      if (!use_all && report.feet[k].exceeds) continue;
      v_c += report.feet[k].v_leg;
      cov_c += report.feet[k].R;
      ++m;
    }
    v_c /= m;
    cov_c /= m;  // the mean R_i, not R_i / m: the feet's errors of one instant are correlated
    const Eigen::Matrix3d g_x = lie::hat3(g);
    const double sa = params_.accel_sigma, sb = params_.accel_bias_sigma;
    const Eigen::Matrix3d cov_imu = anchor_cov_ +
                                    Eigen::Matrix3d::Identity() * (sa * sa * T + sb * sb * T * T) +
                                    T * T * g_x * anchor_att_ * g_x.transpose();
    report.common_d2 = mahalanobis2(v_c - v_imu_, cov_imu + cov_c);
    common_exceeded_ = report.common_d2 > threshold_ ? common_exceeded_ + 1 : 0;
    fired = common_exceeded_ >= params_.confirm_samples;
    report.imu_disagrees = fired;
    report.all_slipping = report.all_slipping || fired;
  } else {
    common_exceeded_ = 0;
  }

  // Renew the anchor while nothing slips (every anchor_window), or when it is too old anyway.
  const bool quiet = !fired && exceeding == 0 && common_exceeded_ == 0;
  if (!anchored_ || (quiet && T >= params_.anchor_window) || T >= params_.max_anchor_age) {
    anchored_ = true;
    anchor_t_ = in.t;
    anchor_cov_ = P.P.block<3, 3>(3, 3);
    anchor_att_ = P.has_attitude ? Eigen::Matrix3d(P.P.block<3, 3>(0, 0))
                                 : Eigen::Matrix3d(Eigen::Matrix3d::Zero());
    v_imu_ = x.v;  // the trusted v_hat, carried to in.t as in check()
    const double gap = in.t - x.t;
    if (gap > 0.0 && gap <= params_.max_propagation) v_imu_ += (R * in.imu.a_m + g) * gap;
  }
}

}  // namespace legkit::slip
