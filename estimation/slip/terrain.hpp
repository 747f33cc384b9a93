// Terrain classes from slip and force statistics (section 57.7, terrain classification).
//
// Online friction estimate. At the onset of a slip the foot is at the edge of its friction cone
// (Coulomb: it slides once |f_t| reaches mu f_n), so the ratio |f_t| / f_n of the ground force at
// the first slipping sample of a foot is a sample of mu; mu_hat is the mean of the last
// kOnsetMemory such samples. A foot that holds without slipping at a ratio rho proves mu >= rho:
// the largest such ratio is a lower bound on mu. f_n = f . n and f_t = f - f_n n, with n the
// ground normal (world z, or the plane fit's normal given by setGroundNormal); only samples with
// f_n >= min_normal_force count (a light foot's ratio is mostly noise).
//
// Classes, with the thresholds of TerrainParams:
//   kIce       mu_hat < ice_mu (0.2) from at least min_onsets slip onsets
//   kHighGrip  mu_hat > high_grip_mu (0.9) from the onsets, or, before that, a foot that held at a
//              ratio above high_grip_mu
//   kNormal    mu_hat in between from the onsets, or, without min_onsets onsets, at least
//              min_stance_time of stance foot-time seen and a lower bound >= ice_mu (not ice,
//              and no evidence of high grip)
//   kUnknown   not enough evidence yet
// Slip-rate statistics beside it: slip onsets per second of stance foot-time and the fraction of
// stance foot-time spent slipping (ice: frequent long slips; dry ground: almost none).
//
// Forces are the ground reaction on each foot in the world frame, by foot id (detect1's
// FootForceFromTorque output, or a force sensor's); a non-finite force is skipped.
//
// Forces estimated from the joint torques. The estimate leaves out the leg's own acceleration, so
// it is worst at touchdown, where the swing leg brakes, and that is where most slips are flagged:
// the foot's impact slide, which is not a foot at the edge of its friction cone either. On the
// dry physics trot (mu 0.6) the onsets flagged 3 ms after touchdown read |f_t| / f_n = 0.10-0.13
// from the estimate (0.25-0.27 true), and mu_hat came out 0.114: "ice". Two guards, both off by
// default (exact forces) and set by estimatedForceParams():
//   min_loaded_time  a ratio is a sample (of mu at an onset, or of the lower bound) only once the
//                    foot has been in stance with f_n >= min_normal_force for this long, the
//                    sample's own dt included: the touchdown transient is over;
//   min_slip_time    an onset gives its ratio (taken at the onset) only once the slip has been
//                    flagged for this long, the onset's own dt included: a flag that drops within
//                    a few samples is more often the detector's false alarm than a slide.
// Measured on `legkit study slip`'s inputs (tests/slip/terrain_physics_test.cpp).
#pragma once

#include <Eigen/Core>
#include <array>

#include "estimation/slip/slip_detector.hpp"

namespace legkit::slip {

enum class TerrainClass { kUnknown, kIce, kNormal, kHighGrip };

// "unknown", "ice", "normal", "high-grip".
const char* terrainClassName(TerrainClass c);

struct TerrainParams {
  double ice_mu = 0.2;             // mu_hat below: ice
  double high_grip_mu = 0.9;       // mu_hat above: high grip
  double min_normal_force = 20.0;  // [N] a force sample counts only above this
  int min_onsets = 3;              // slip onsets before mu_hat decides
  double min_stance_time = 2.0;    // [s] of stance foot-time before the no-slip evidence decides
  double min_loaded_time = 0.0;    // [s] loaded stance before a ratio counts (see above)
  double min_slip_time = 0.0;      // [s] a slip must hold before its onset counts (see above)
};

// The parameters for forces estimated from the joint torques (contact::FootForceFromTorque):
// min_loaded_time 30 ms (a tenth of the trot's 300 ms stance), min_slip_time 5 ms (five samples
// at 1 kHz); the rest as TerrainParams{}.
TerrainParams estimatedForceParams();

class TerrainClassifier {
 public:
  static constexpr int kOnsetMemory = 16;

  // Throws std::invalid_argument for thresholds that are not 0 < ice_mu < high_grip_mu, a
  // negative force bound, min_onsets < 1 or a negative stance, loaded or slip time.
  explicit TerrainClassifier(const TerrainParams& params = {});

  void reset();
  // One sample: the slip report of that instant, the world ground force on each foot by foot id
  // (forces[0..num_forces)), and the time since the previous sample [s].
  TerrainClass update(const SlipReport& report, const Eigen::Vector3d* forces, int num_forces,
                      double dt);
  // The ground normal the forces are split along (unit; e.g. fitGroundPlane's normal).
  void setGroundNormal(const Eigen::Vector3d& n) { normal_ = n.normalized(); }

  TerrainClass terrain() const { return class_; }
  double frictionEstimate() const;  // mu_hat (NaN before the first onset)
  double frictionLowerBound() const { return mu_lower_; }
  int onsets() const { return onsets_; }              // onsets that gave a friction sample
  double stanceTime() const { return stance_time_; }  // stance foot-time seen [s]
  double slipRate() const;      // slip onsets per second of stance foot-time [1/s]
  double slipFraction() const;  // slipping foot-time / stance foot-time

 private:
  TerrainClass classify() const;

  TerrainParams params_;
  Eigen::Vector3d normal_ = Eigen::Vector3d::UnitZ();
  std::array<bool, kMaxFeet> was_slipping_{};
  std::array<double, kMaxFeet> loaded_time_{};  // stance with f_n >= min_normal_force so far [s]
  std::array<double, kMaxFeet> slip_held_{};    // flagged slipping since the onset [s]
  // The ratio taken at the foot's current slip's onset, waiting for min_slip_time; NaN: none.
  std::array<double, kMaxFeet> onset_ratio_{};
  std::array<double, kOnsetMemory> onset_mu_{};
  int onsets_ = 0;       // onsets with a usable force since reset (the ring holds the last ones)
  int slip_onsets_ = 0;  // every onset, with or without a usable force
  double mu_lower_ = 0.0;
  double stance_time_ = 0.0, slip_time_ = 0.0;  // foot-time [s]
  TerrainClass class_ = TerrainClass::kUnknown;
};

}  // namespace legkit::slip
