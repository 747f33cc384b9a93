#include "estimation/contact_pipeline.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace legkit {

ContactPipeline::ContactPipeline(const LogFrontend& frontend, const PipelineOptions& options,
                                 std::unique_ptr<contact::ContactDetector> detector)
    : frontend_(frontend),
      options_(options),
      rolls_(options.rolling_foot && frontend.layout().joints && frontend.extrinsic().isIdentity()),
      detector_(std::move(detector)),
      rolling_(frontend.quadruped().geometry()),
      guard_(options.slip_params, options.slip) {
  touchdown_t_.fill(-std::numeric_limits<double>::infinity());
  if (!(options.no_contact_bound > 0.0) || !std::isfinite(options.no_contact_bound)) {
    throw std::invalid_argument("ContactPipeline: no_contact_bound must be positive, got " +
                                std::to_string(options.no_contact_bound));
  }
  if (!(options.settle_time >= 0.0) || !std::isfinite(options.settle_time)) {
    throw std::invalid_argument("ContactPipeline: settle_time must be >= 0, got " +
                                std::to_string(options.settle_time));
  }
  if (!detector_ && options.contact != "truth") {
    throw std::invalid_argument("ContactPipeline: no detector for the contact source '" +
                                options.contact + "'");
  }
  if (!detector_ && !frontend.layout().contact) {
    throw std::invalid_argument(
        "contact source 'truth': the log has no contact columns (choose a detector)");
  }
  chain_ = dynamic_cast<const contact::FallbackDetector*>(detector_.get());
  if (chain_) {
    for (int k = 0; k < chain_->size(); ++k)
      diagnostics_.sources.push_back(chain_->detector(k).name());
  } else {
    diagnostics_.sources.push_back(source());
  }
  decider_.fill(-1);
}

ContactPipeline::ContactPipeline(const LogFrontend& frontend, const PipelineOptions& options,
                                 const contact::DetectorContext& context)
    : ContactPipeline(
          frontend, options,
          options.contact == "truth" ? nullptr : contact::makeDetector(options.contact, context)) {}

ContactPipeline::ContactPipeline(const io::LogLayout& layout,
                                 const model::QuadrupedKinematics& kinematics,
                                 const FrontendNoise& noise, const PipelineOptions& options,
                                 std::unique_ptr<contact::ContactDetector> detector)
    : ContactPipeline(LogFrontend(layout, kinematics, noise), options, std::move(detector)) {}

ContactPipeline::ContactPipeline(const io::LogLayout& layout,
                                 const model::QuadrupedKinematics& kinematics,
                                 const FrontendNoise& noise, const PipelineOptions& options,
                                 const contact::DetectorContext& context)
    : ContactPipeline(LogFrontend(layout, kinematics, noise), options, context) {}

double settleWeight(double since_touchdown, double settle_time) {
  return since_touchdown < settle_time ? 0.0 : 1.0;
}

std::string ContactPipeline::source() const {
  return detector_ ? detector_->name() : "truth";
}

void ContactPipeline::reset() {
  if (detector_) detector_->reset();
  rolling_.reset();
  w_admitted_.setZero();
  velocities_.reset();
  guard_.reset();
  health_ = Health{};
  last_stance_t_.reset();
  silent_ = false;
  down_.fill(false);
  settling_.fill(false);
  // Feet already down at a run's first row are settled.
  touchdown_t_.fill(-std::numeric_limits<double>::infinity());
  diagnostics_.samples = 0;
  diagnostics_.num_feet = 0;
  diagnostics_.feet = {};
  decider_.fill(-1);
}

const StepInput& ContactPipeline::step(const io::LogRow& row, double dt, const EstimateSample& x,
                                       const std::optional<BaseCovariance>& P) {
  const int num_feet = frontend_.layout().num_feet;
  if (detector_) {
    const contact::BaseFeedback base = contact::feedbackFrom(x);
    contacts_ = detector_->update(frontend_.signals(row, dt, base));
  } else {
    contacts_.t = row.t;
    contacts_.num_feet = num_feet;
    for (int foot = 0; foot < num_feet; ++foot) {
      contact::FootContact& c = contacts_.feet[foot];
      c.contact = row.contact[foot];
      c.probability = c.contact ? 1.0 : 0.0;
      c.force = frontend_.layout().force ? row.force[foot] : std::nan("");
      c.problem = nullptr;
    }
  }
  // Touchdown settling: which feet the source has put down less than settle_time ago (a foot down
  // at the first row, when last_stance_t_ is still empty, is no touchdown). They stay in input_
  // for the slip check and are taken out only of what the filter receives, below.
  for (int foot = 0; foot < contacts_.num_feet; ++foot) {
    const contact::FootContact& c = contacts_.feet[foot];
    const bool down = c.usable() && c.contact;
    FootContactDiagnostics& d = diagnostics_.feet[foot];
    if (down && !down_[foot] && last_stance_t_) {
      touchdown_t_[foot] = row.t;
      ++d.touchdowns;
    }
    d.stance += down ? 1 : 0;
    down_[foot] = down;
    settling_[foot] = settleWeight(row.t - touchdown_t_[foot], options_.settle_time) == 0.0;
    // Which source decided the foot (an index of diagnostics_.sources, `none` for none), and a
    // change of it: a hand-over, down the chain when the source that decided before had a problem.
    const int none = static_cast<int>(diagnostics_.sources.size());
    const int now = chain_ ? (chain_->source()[foot] < 0 ? none : chain_->source()[foot])
                           : (c.usable() ? 0 : none);
    if (now < none) {
      ++d.decided[now];
    } else {
      ++d.undecided;
    }
    const int before = decider_[foot];
    if (before >= 0 && now != before) {
      ++d.handovers;
      if (now > before) {
        ++d.handovers_down;
        const char* why = chain_ ? chain_->problem(foot, before) : c.problem;
        if (why != nullptr) d.countProblem(why);
      }
    }
    decider_[foot] = now;
  }
  ++diagnostics_.samples;
  diagnostics_.num_feet = contacts_.num_feet;
  if (detector_) {
    input_ = frontend_.input(row, dt, contacts_, options_.soft, &velocities_);
  } else {
    input_ = frontend_.input(row, dt, &velocities_);  // the log's flags, as always read
  }
  if (rolls_) {
    const InputLimits& limit = options_.limits;
    if (row.gyro.allFinite() && row.gyro.cwiseAbs().maxCoeff() <= limit.gyro_max) {
      w_admitted_ = row.gyro;  // else the last admitted sample stays held (Estimator's contract)
    }
    rolling_.apply(input_, x.q.toRotationMatrix(), w_admitted_, row.q, row.dq);
  }
  // Silence of the contact source (a slip reaction dropping feet is not silence): no stance foot
  // since last_stance_t_ for longer than the bound.
  if (input_.num_contacts > 0 || !last_stance_t_) {
    last_stance_t_ = row.t;
    silent_ = false;
  } else if (!silent_ && row.t - *last_stance_t_ > options_.no_contact_bound) {
    health_.record(Fault::kNoContact, row.t);
    silent_ = true;
  }
  // The slip check sees every foot the source put down, settling or not (a slide at touchdown
  // counts towards its confirmation and its all-feet test); the filter gets the settling ones at
  // p_c = 0: a swing foot's random walk and a measurement covariance that says "ignore it".
  const StepInput& guarded = guard_.apply(input_, x, P, reacted_, &slip_report_);
  for (int foot = 0; foot < contacts_.num_feet; ++foot) {
    diagnostics_.feet[foot].slipping += slip_report_.slipping(foot) ? 1 : 0;
  }
  bool any_settling = false;
  for (const ContactMeasurement& c : guarded.stance()) any_settling |= settling_[c.foot];
  if (!any_settling) return guarded;
  settled_ = guarded;
  for (int k = 0; k < settled_.num_contacts; ++k) {
    ContactMeasurement& c = settled_.contacts[k];
    if (!settling_[c.foot]) continue;
    c.cov = contact::softMeasurementCov(c.cov, 0.0, options_.soft);
    c.probability = 0.0;
    ++diagnostics_.feet[c.foot].settled;
  }
  return settled_;
}

}  // namespace legkit
