// Reference solution of exercise 57.X.
#include <cmath>
#include <stdexcept>

#include "estimation/contact_pipeline.hpp"
#include "estimation/estimators.hpp"
#include "ex57_X.hpp"

namespace ex57_X {

IceRun runOnIce(const legkit::io::Log& log, const legkit::sim::FrictionPatch& ice,
                const std::string& estimator, legkit::slip::SlipReaction reaction) {
  if (!log.layout.joints || !log.layout.ground_truth || !log.layout.contact_truth)
    throw std::invalid_argument("runOnIce: the log needs joints, ground truth and contact truth");
  IceRun run;
  if (log.rows.empty()) return run;
  legkit::PipelineOptions options;
  options.slip = reaction;
  const legkit::model::QuadrupedKinematics kin;
  legkit::ContactPipeline pipeline(log.layout, kin, legkit::FrontendNoise{}, options);
  const std::unique_ptr<legkit::Estimator> filter = legkit::makeEstimator(estimator);
  const legkit::io::LogRow& first = log.rows.front();
  legkit::EstimateSample x0;
  x0.t = first.t;
  x0.q = first.gt_q;
  x0.v = first.gt_v;
  x0.p = first.gt_p;
  filter->reset(x0);
  double sum_sq = 0.0;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const legkit::io::LogRow& row = log.rows[k];
    const double dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
    filter->step(pipeline.step(row, dt, filter->estimate(), filter->covariance()));
    const legkit::io::FootTruth& foot = row.gt_feet[kIceFoot];
    if (std::isnan(run.first_true_slip) && foot.contact && foot.slip_speed > kSlipSpeed) {
      const Eigen::Vector3d at =
          row.gt_p + row.gt_q * kin.footPosition(kIceFoot, row.q.segment<3>(3 * kIceFoot));
      const bool on_ice = at.x() >= ice.min.x() && at.x() <= ice.max.x() && at.y() >= ice.min.y() &&
                          at.y() <= ice.max.y();
      if (on_ice) run.first_true_slip = row.t;
    }
    if (!std::isnan(run.first_true_slip) && std::isnan(run.first_detection) &&
        pipeline.slipReport().slipping(kIceFoot))
      run.first_detection = row.t;
    const legkit::EstimateSample x = filter->estimate();
    sum_sq += (x.v - row.gt_v).squaredNorm();
    if (k + 1 == log.rows.size()) run.position_error = (x.p - row.gt_p).norm();
  }
  run.velocity_rmse = std::sqrt(sum_sq / static_cast<double>(log.rows.size()));
  return run;
}

}  // namespace ex57_X
