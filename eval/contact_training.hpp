// The training set of the logistic contact probability (section 57.6, method 5; exercise 57.6.2):
// simulated physics runs, their log rows turned into the detector's features, the physics' true
// contact as labels, and the fit of estimation/contact/logistic_training.hpp. The kit's
// coefficients come out of this code and a seed; none is typed in by hand.
//
// Training runs (sim::simulatePhysics, 1 kHz rows): physics-trot and physics-walk, 10 s each, and
// physics-ice (its 10 s, up to the fall), with seeds seed + 1000, + 1001, + 1002: an evaluation
// that simulates with seeds below 1000 never scores the model on its own training data.
//
// Features as the detector computes them (contactFeatures) from what the run pipeline hands a
// detector (LogFrontend::signals: the foot sensor's force, the legs' FK and J dq from
// model::QuadrupedKinematics, the gyro), the base velocity and attitude, and the planned phase of
// the scenario's gait. One exception: the base velocity and attitude for TRAINING come from the
// log's ground truth (gt_v, gt_q), not from an estimator, so that the fit does not depend on
// which filter ran. At evaluation time a detector gets the estimator's previous estimate
// (BaseFeedback) and never the truth.
#pragma once

#include <vector>

#include "estimation/contact/contact_detector.hpp"
#include "estimation/contact/gait_schedule.hpp"
#include "estimation/contact/logistic_contact.hpp"
#include "estimation/contact/logistic_training.hpp"
#include "io/log.hpp"
#include "model/quadruped.hpp"
#include "sim/physics_scenario.hpp"

namespace legkit::eval {

// The planned schedule a robot running `scenario` would publish: its gait, clock started at
// stand_time.
contact::GaitSchedule plannedGait(const sim::PhysicsScenario& scenario);

// The base feedback of a perfect estimator: the row's true attitude and velocity (valid).
contact::BaseFeedback truthFeedback(const io::LogRow& row);

// Appends one sample per foot and row of `log` (features of LogFrontend::signals with
// truthFeedback, phase from `gait` or 0 when nullptr; label gt_feet[foot].contact). Throws
// std::invalid_argument for a log without joint, force, ground-truth or contact_truth columns.
void appendTrainingSamples(const io::Log& log, const contact::GaitSchedule* gait,
                           const model::QuadrupedKinematics& kinematics,
                           std::vector<contact::ContactFeatures>& samples,
                           std::vector<bool>& labels);

// Simulates the three training runs from `seed` (see above) and fits the model. Deterministic:
// the same seed gives the same weights.
contact::LogisticModel trainContactModel(unsigned seed,
                                         const contact::TrainingOptions& options = {});

}  // namespace legkit::eval
