// Reference solution of exercise 57.X.
#include <cmath>
#include <stdexcept>

#include "estimation/estimators.hpp"
#include "ex57_X.hpp"

namespace ex57_X {

PipelineEstimator::PipelineEstimator(const legkit::io::LogLayout& layout,
                                     const std::string& estimator,
                                     legkit::slip::SlipReaction reaction)
    : estimator_(legkit::makeEstimator(estimator)) {
  legkit::PipelineOptions options;
  options.slip = reaction;
  pipeline_ = std::make_unique<legkit::ContactPipeline>(
      layout, legkit::model::QuadrupedKinematics{}, legkit::FrontendNoise{}, options);
}

bool PipelineEstimator::update(const legkit::io::LogRow& row, legkit::sim::BaseEstimate& out) {
  if (!started_) {
    legkit::EstimateSample x0;
    x0.t = row.t;
    x0.q = row.gt_q;
    x0.v = row.gt_v;
    x0.p = row.gt_p;
    estimator_->reset(x0);
  }
  const double dt = started_ ? row.t - t_previous_ : 0.0;
  started_ = true;
  t_previous_ = row.t;
  // The detection and the slip check use the estimate of the previous step (57.6's rule).
  estimator_->step(pipeline_->step(row, dt, estimator_->estimate(), estimator_->covariance()));
  const legkit::EstimateSample x = estimator_->estimate();
  out.R = x.q.toRotationMatrix();
  out.p = x.p;
  out.v = x.v;
  return true;
}

IceRun runOnIce(const legkit::io::Log& log, const legkit::sim::FrictionPatch& ice,
                const std::string& estimator, legkit::slip::SlipReaction reaction) {
  if (!log.layout.joints || !log.layout.ground_truth || !log.layout.contact_truth)
    throw std::invalid_argument("runOnIce: the log needs joints, ground truth and contact truth");
  IceRun run;
  if (log.rows.empty()) return run;
  const legkit::model::QuadrupedKinematics kin;
  PipelineEstimator filter(log.layout, estimator, reaction);
  double sum_sq = 0.0;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const legkit::io::LogRow& row = log.rows[k];
    legkit::sim::BaseEstimate x;
    filter.update(row, x);
    const legkit::io::FootTruth& foot = row.gt_feet[kIceFoot];
    if (std::isnan(run.first_true_slip) && foot.contact && foot.slip_speed > kSlipSpeed) {
      const Eigen::Vector3d at =
          row.gt_p + row.gt_q * kin.footPosition(kIceFoot, row.q.segment<3>(3 * kIceFoot));
      const bool on_ice = at.x() >= ice.min.x() && at.x() <= ice.max.x() && at.y() >= ice.min.y() &&
                          at.y() <= ice.max.y();
      if (on_ice) run.first_true_slip = row.t;
    }
    if (!std::isnan(run.first_true_slip) && std::isnan(run.first_detection) &&
        filter.pipeline().slipReport().slipping(kIceFoot))
      run.first_detection = row.t;
    sum_sq += (x.v - row.gt_v).squaredNorm();
    if (k + 1 == log.rows.size()) run.position_error = (x.p - row.gt_p).norm();
  }
  run.velocity_rmse = std::sqrt(sum_sq / static_cast<double>(log.rows.size()));
  return run;
}

}  // namespace ex57_X
