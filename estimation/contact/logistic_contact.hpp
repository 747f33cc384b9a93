// Method 5 of section 57.6: the contact probability of a logistic regression (Camurri et al.,
// 2017), instead of a hard decision:
//   p_c = sigma(w1 F_n + w2 |v_foot| + w3 phi + b),   sigma(z) = 1 / (1 + e^-z)      (57.6, m. 5)
// with three features per foot:
//   F_n       the foot sensor's normal force [N],
//   |v_foot|  the foot's world speed from the leg kinematics and the previous base estimate,
//             v_foot = v + R (omega x B_p_f + B_v_f) (omega the gyro) [m/s],
//   phi       the planned gait phase in [0, 1) (gait_schedule.hpp's plannedPhase; 0 without a
//             schedule).
// The model stores the scaling of its training set (mean and standard deviation per feature),
// and its weights act on the scaled features: z = b + sum_i w_i (x_i - mean_i) / scale_i. A
// weight of exactly 0 means the model does not use that feature (trained without it), and the
// detector then neither needs nor reads it: a model trained with use_force = false
// (logistic_training.hpp) runs on a robot without foot sensors.
//
// The weights are never typed in: logistic_training.hpp fits them, and eval/contact_training.hpp
// fits them on simulated physics runs from a seed.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross
#include <limits>
#include <optional>
#include <string>

#include "estimation/contact/contact_detector.hpp"
#include "estimation/contact/gait_schedule.hpp"

namespace legkit::contact {

struct LogisticModel {
  Eigen::Vector4d w = Eigen::Vector4d::Zero();  // (b, w_F, w_v, w_phi), on the scaled features
  // Feature scaling, (force, foot_speed, phase): x_scaled = (x - mean) / scale.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();

  bool usesForce() const { return w[1] != 0.0; }
  bool usesFootSpeed() const { return w[2] != 0.0; }
  bool usesPhase() const { return w[3] != 0.0; }
};

struct ContactFeatures {
  double force = std::numeric_limits<double>::quiet_NaN();       // F_n [N]
  double foot_speed = std::numeric_limits<double>::quiet_NaN();  // |v_foot| [m/s]
  double phase = 0.0;                                            // phi in [0, 1)
};

// The features of foot `foot`: the sensor's force as given (NaN when there is none), the foot
// speed (NaN without the leg's kinematics or a valid base estimate), the planned phase at
// signals.t (0 when gait is nullptr).
ContactFeatures contactFeatures(const ContactSignals& signals, int foot, const GaitSchedule* gait);

// sigma(w . (1, x_scaled)); NaN when a feature the model uses is NaN.
double contactProbability(const LogisticModel& model, const ContactFeatures& x);

struct LogisticParams {
  // Contact turns on when p_c rises above 0.5 + hysteresis and off when it falls below
  // 0.5 - hysteresis (0: the plain p_c > 0.5). The plain rule chatters: near a touchdown the
  // sensor's 2 N noise swings p_c across 0.5 again and again (the kit's model, seed-3 trot, 6 s:
  // 208 contact changes against the truth's 78); 0.4 (on above 0.9, off below 0.1) leaves 82 and
  // the best F1 (tests/contact/contact_training_test.cpp).
  double hysteresis = 0.4;
};

class LogisticContactDetector : public ContactDetector {
 public:
  // Throws std::invalid_argument for a model with a non-finite weight or a non-positive scale,
  // a model that uses the phase without a gait schedule, or a hysteresis outside [0, 0.5).
  explicit LogisticContactDetector(const LogisticModel& model,
                                   const std::optional<GaitSchedule>& gait = std::nullopt,
                                   const LogisticParams& params = {});

  std::string name() const override { return "probabilistic"; }
  void reset() override;
  // probability = p_c, force = the sensor's force (NaN when unused), contact by the hysteresis
  // rule. Problems per foot: "force is NaN" (a model that uses it), "no leg kinematics" or "no
  // base estimate" (a model that uses the foot speed), "foot speed not finite".
  ContactEstimate update(const ContactSignals& signals) override;

  const LogisticModel& model() const { return model_; }

 private:
  LogisticModel model_;
  std::optional<GaitSchedule> gait_;
  LogisticParams params_;
  Eigen::Vector3d a_;  // the weights in raw units (force, foot speed, phase)
  double b_;           // the bias in raw units
  std::array<bool, kMaxFeet> contact_{};
};

}  // namespace legkit::contact
