#include "eval/contact_training.hpp"

#include <stdexcept>
#include <string>

#include "estimation/log_frontend.hpp"
#include "sim/physics_simulator.hpp"

namespace legkit::eval {

contact::GaitSchedule plannedGait(const sim::PhysicsScenario& scenario) {
  contact::GaitSchedule g;
  g.period = scenario.gait.period;
  g.duty = scenario.gait.duty;
  for (int leg = 0; leg < model::kNumLegs; ++leg) g.offset[leg] = scenario.gait.offset[leg];
  g.start = scenario.stand_time;
  g.num_feet = model::kNumLegs;
  return g;
}

contact::BaseFeedback truthFeedback(const io::LogRow& row) {
  contact::BaseFeedback b;
  b.valid = true;
  b.R = row.gt_q.toRotationMatrix();
  b.v = row.gt_v;
  b.p = row.gt_p;
  return b;
}

void appendTrainingSamples(const io::Log& log, const contact::GaitSchedule* gait,
                           const model::QuadrupedKinematics& kinematics,
                           std::vector<contact::ContactFeatures>& samples,
                           std::vector<bool>& labels) {
  if (!log.layout.joints || !log.layout.force || !log.layout.contact_truth ||
      !log.layout.ground_truth)
    throw std::invalid_argument(
        "appendTrainingSamples: the log needs joint, force, ground-truth and contact_truth "
        "columns");
  samples.reserve(samples.size() + model::kNumLegs * log.rows.size());
  labels.reserve(labels.size() + model::kNumLegs * log.rows.size());
  const LogFrontend frontend(log.layout, kinematics);
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const io::LogRow& row = log.rows[k];
    const double dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
    const contact::ContactSignals s = frontend.signals(row, dt, truthFeedback(row));
    for (int leg = 0; leg < model::kNumLegs; ++leg) {
      samples.push_back(contact::contactFeatures(s, leg, gait));
      labels.push_back(row.gt_feet[leg].contact);
    }
  }
}

contact::LogisticModel trainContactModel(unsigned seed, const contact::TrainingOptions& options) {
  const model::QuadrupedKinematics kinematics;
  std::vector<contact::ContactFeatures> samples;
  std::vector<bool> labels;
  const char* const runs[] = {"physics-trot", "physics-walk", "physics-ice"};
  for (unsigned k = 0; k < 3; ++k) {
    sim::PhysicsOptions o = sim::PhysicsOptions::forScenario(runs[k]);
    o.duration = 10.0;
    o.seed = seed + 1000 + k;
    const sim::PhysicsResult run = sim::simulatePhysics(o);
    const contact::GaitSchedule gait = plannedGait(o.scenario);
    appendTrainingSamples(run.log, &gait, kinematics, samples, labels);
  }
  return contact::trainLogistic(samples, labels, options);
}

}  // namespace legkit::eval
