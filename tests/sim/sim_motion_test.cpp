// The simulated motion is kinematically consistent: stance feet stay put in the world, the joint
// angles put the feet where the foot trajectories say, the joint rates are the derivative of the
// angles, and the gaits have the advertised contact timing.
#include <catch2/catch.hpp>
#include <cmath>

#include "sim/quadruped_motion.hpp"
#include "sim_test_support.hpp"

using namespace legkit;
using sim::test::footInWorld;
using sim::test::legAngles;
using sim::test::legRates;

TEST_CASE("Stance feet do not move in the world; FK(q) follows the foot trajectory",
          "[57.3][sim]") {
  const model::QuadrupedKinematics kin;
  for (const std::string& name : sim::scenarioNames()) {
    INFO("scenario " << name);
    const sim::SimOptions options = sim::test::noiselessRun(name, 4.0);
    const sim::SimResult run = sim::simulate(options);
    const sim::QuadrupedMotion motion(options.scenario, kin);
    double stance_drift = 0.0, fk_error = 0.0;
    int stance_samples = 0;
    for (int leg = 0; leg < model::kNumLegs; ++leg) {
      Eigen::Vector3d anchor = Eigen::Vector3d::Zero();
      bool in_stance = false;
      for (const io::LogRow& row : run.log.rows) {
        const Eigen::Vector3d p = footInWorld(kin, row, leg);
        // FK(q) against the analytic foot trajectory, in the body frame.
        const Eigen::Vector3d expected =
            row.gt_q.toRotationMatrix().transpose() * (motion.foot(leg, row.t).p - row.gt_p);
        fk_error =
            std::max(fk_error, (kin.footPosition(leg, legAngles(row, leg)) - expected).norm());
        if (row.contact[leg]) {
          if (!in_stance) anchor = p;
          stance_drift = std::max(stance_drift, (p - anchor).norm());
          ++stance_samples;
          CHECK(std::abs(p.z() - kin.geometry().foot_radius) < 1e-9);  // on the ground
        }
        in_stance = row.contact[leg];
      }
    }
    CHECK(stance_samples > 0);
    CHECK(stance_drift < 1e-9);
    CHECK(fk_error < 1e-9);
  }
}

TEST_CASE("Joint rates are the time derivative of the joint angles", "[57.3][sim]") {
  const model::QuadrupedKinematics kin;
  for (const char* name : {"trot", "bound", "turn"}) {
    INFO("scenario " << name);
    const sim::SimResult run = sim::simulate(sim::test::noiselessRun(name, 3.0));
    const auto& rows = run.log.rows;
    double worst = 0.0, largest = 0.0;
    for (std::size_t k = 1; k + 1 < rows.size(); ++k) {
      const double dt2 = rows[k + 1].t - rows[k - 1].t;
      const Eigen::Matrix<double, 12, 1> central = (rows[k + 1].q - rows[k - 1].q) / dt2;
      worst = std::max(worst, (central - rows[k].dq).cwiseAbs().maxCoeff());
      largest = std::max(largest, rows[k].dq.cwiseAbs().maxCoeff());
    }
    CHECK(largest > 1.0);  // the legs really move
    CHECK(worst < 2e-3 * largest);
    // And J(q) dq is the foot velocity relative to the body: the same in the body frame.
    for (std::size_t k = 1; k + 1 < rows.size(); k += 97) {
      for (int leg = 0; leg < model::kNumLegs; ++leg) {
        const Eigen::Vector3d v =
            kin.footJacobian(leg, legAngles(rows[k], leg)) * legRates(rows[k], leg);
        const Eigen::Vector3d fd = (kin.footPosition(leg, legAngles(rows[k + 1], leg)) -
                                    kin.footPosition(leg, legAngles(rows[k - 1], leg))) /
                                   (rows[k + 1].t - rows[k - 1].t);
        CHECK((v - fd).norm() < 5e-3);
      }
    }
  }
}

namespace {

// Lengths (in samples) of the runs of equal contact flags of one leg after time t0, without the
// first and last (cut) runs.
std::vector<int> runLengths(const io::Log& log, int leg, double t0, bool stance) {
  std::vector<int> runs;
  int length = 0;
  bool current = false, started = false;
  for (const io::LogRow& row : log.rows) {
    if (row.t < t0) continue;
    if (!started) {
      current = row.contact[leg];
      started = true;
    }
    if (row.contact[leg] == current) {
      ++length;
      continue;
    }
    if (current == stance) runs.push_back(length);
    current = row.contact[leg];
    length = 1;
  }
  if (!runs.empty()) runs.erase(runs.begin());
  return runs;
}

}  // namespace

TEST_CASE("The 2 Hz trot: 300 ms stance, 200 ms swing, diagonal pairs together", "[57.3][sim]") {
  const sim::SimResult run = sim::simulate(sim::test::noiselessRun("trot", 5.0));
  const double start = sim::scenarioByName("trot").stand_time;
  for (const io::LogRow& row : run.log.rows) {
    if (row.t < start) {
      CHECK((row.contact[0] && row.contact[1] && row.contact[2] && row.contact[3]));
    }
    CHECK(row.contact[model::FL] == row.contact[model::RR]);
    CHECK(row.contact[model::FR] == row.contact[model::RL]);
    CHECK((row.contact[model::FL] || row.contact[model::FR]));  // never airborne
  }
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    const std::vector<int> stance = runLengths(run.log, leg, start, true);
    const std::vector<int> swing = runLengths(run.log, leg, start, false);
    REQUIRE(stance.size() >= 5);
    REQUIRE(swing.size() >= 5);
    for (int n : stance) CHECK(std::abs(n - 300) <= 1);
    for (int n : swing) CHECK(std::abs(n - 200) <= 1);
  }
  // The two pairs swing half a period apart: FL lifts off 250 ms after FR.
  const sim::Gait gait = sim::Gait::trot(2.0);
  CHECK(sim::liftoffTime(gait, model::FL, 3) - sim::liftoffTime(gait, model::FR, 3) ==
        Approx(0.25).margin(1e-12));
}

TEST_CASE("The bound has flight phases in which the base falls freely", "[57.3][sim]") {
  const sim::SimOptions options = sim::test::noiselessRun("bound", 4.0);
  const sim::SimResult run = sim::simulate(options);
  const double steady = options.scenario.stand_time + options.scenario.ramp_duration;
  int flight = 0;
  for (const io::LogRow& row : run.log.rows) {
    const bool airborne = !(row.contact[0] || row.contact[1] || row.contact[2] || row.contact[3]);
    CHECK(row.contact[model::FL] == row.contact[model::FR]);
    if (airborne && row.t > steady) {
      ++flight;
      CHECK(row.acc.norm() < 1e-9);  // specific force of free fall: zero
    }
  }
  CHECK(flight == Approx(0.4 * (4.0 - steady) * 1000).epsilon(0.02));  // 2 x 20 % of each period
}
