// Exercise 57.X (across chapters): the front-right foot steps onto ice. When does the kit see the
// slip, and what does the estimate do with and without slip handling?
#pragma once

#include <limits>
#include <memory>
#include <string>

#include "estimation/contact_pipeline.hpp"
#include "estimation/estimator.hpp"
#include "estimation/slip/slip_guard.hpp"
#include "io/log.hpp"
#include "sim/base_state_source.hpp"
#include "sim/physics_scenario.hpp"

namespace ex57_X {

constexpr int kIceFoot = 1;         // FR, the foot whose path crosses the ice patch
constexpr double kSlipSpeed = 0.1;  // a true slip: in contact and sliding faster than this [m/s]

struct IceRun {
  // First row where foot kIceFoot is on the ice (the foot point gt_p + R FK(q) inside the patch's
  // x-y box, R from gt_q), truly in contact (gt_feet contact) and sliding faster than kSlipSpeed
  // (gt_feet slip_speed); NaN if none.
  double first_true_slip = std::numeric_limits<double>::quiet_NaN();  // [s]
  // First row at or after first_true_slip where the pipeline's slip check finds kIceFoot
  // slipping (ContactPipeline::slipReport().slipping(kIceFoot)); NaN if none.
  double first_detection = std::numeric_limits<double>::quiet_NaN();  // [s]
  double velocity_rmse = 0.0;   // RMS over all rows of |v_hat - v| [m/s]
  double position_error = 0.0;  // |p_hat - p| at the last row [m]
};

// The kit's estimator `estimator` (legkit::makeEstimator) behind a legkit::ContactPipeline on the
// log's contact flags ("truth"), with the slip reaction given (other options at their defaults),
// the front end's default noise and the default quadruped kinematics, one log row at a time.
// It is also a sim::BaseStateSource: in closed loop the physics simulator's controller acts on
// its estimate.
class PipelineEstimator : public legkit::sim::BaseStateSource {
 public:
  // Throws std::invalid_argument for an unknown estimator or a layout the pipeline refuses.
  PipelineEstimator(const legkit::io::LogLayout& layout, const std::string& estimator,
                    legkit::slip::SlipReaction reaction);
  // At the first row: resets the estimator to the row's ground truth (pose, velocity; t of the
  // row). Every row: the pipeline's step with the estimator's estimate and covariance after the
  // previous row (at the first row, after the reset), then the estimator's step with what the
  // pipeline returns; `out` is the new estimate. Always true.
  bool update(const legkit::io::LogRow& row, legkit::sim::BaseEstimate& out) override;

  const legkit::Estimator& estimator() const { return *estimator_; }
  const legkit::ContactPipeline& pipeline() const { return *pipeline_; }

 private:
  std::unique_ptr<legkit::Estimator> estimator_;
  std::unique_ptr<legkit::ContactPipeline> pipeline_;
  bool started_ = false;
  double t_previous_ = 0.0;
};

// A PipelineEstimator over every row of the log. `ice` is the scenario's ice patch. Throws
// std::invalid_argument for a log without joints, ground truth or contact truth.
IceRun runOnIce(const legkit::io::Log& log, const legkit::sim::FrictionPatch& ice,
                const std::string& estimator, legkit::slip::SlipReaction reaction);

}  // namespace ex57_X
