#include "closed_loop.hpp"

#include "estimation/estimators.hpp"

namespace legkit::tools {

io::LogLayout physicsLogLayout(bool ground_truth) {
  io::LogLayout layout;
  layout.joints = layout.torque = layout.force = layout.contact = true;
  layout.ground_truth = layout.contact_truth = ground_truth;
  return layout;
}

EstimatorBaseState::EstimatorBaseState(const std::string& name, const io::LogLayout& layout,
                                       const FrontendNoise& noise)
    : estimator_(makeEstimator(name)),
      layout_(layout),
      frontend_(layout, model::QuadrupedKinematics(), noise) {}

bool EstimatorBaseState::update(const io::LogRow& row, sim::BaseEstimate& out) {
  if (!started_) {
    EstimateSample x0;
    x0.t = row.t;
    if (layout_.ground_truth) {
      x0.q = row.gt_q;
      x0.v = row.gt_v;
      x0.p = row.gt_p;
    } else {  // at rest the accelerometer reads -R^T g: world up seen from the body
      x0.q = Eigen::Quaterniond::FromTwoVectors(row.acc.normalized(), Eigen::Vector3d::UnitZ());
    }
    estimator_->reset(x0);
    started_ = true;
    t_previous_ = row.t;
  }
  estimator_->step(frontend_.input(row, row.t - t_previous_));
  t_previous_ = row.t;
  const EstimateSample x = estimator_->estimate();
  out.R = x.q.toRotationMatrix();
  out.p = x.p;
  out.v = x.v;
  return true;
}

}  // namespace legkit::tools
