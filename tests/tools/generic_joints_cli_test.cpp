// Issue 14 item 5 end to end: a robot of generic joints described by its own model file. The kit's
// Go2 written as MJCF (model::quadrupedMjcf), a 3 s analytic trot log whose q_/dq_ columns are
// renamed joint<k>_q/_dq, run by `legkit run --log --config robot.yaml` with the robot section
// naming the MJCF's base body and foot sites: every estimator's errors are those of the same log
// with the quadruped's own joint columns (the analytic Go2 legs). Both runs on the log's contact
// flags, without slip reaction, settling or rolling foot (the analytic trot's feet are points).
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/log_reader.hpp"
#include "io/log_writer.hpp"
#include "legkit_cli.hpp"
#include "model/mjcf.hpp"
#include "model/quadruped.hpp"
#include "model/quadruped_inertia.hpp"

namespace fs = std::filesystem;
using namespace legkit;

namespace {

using test::runLegkit;
constexpr auto summary = test::readSummary;

}  // namespace

TEST_CASE("legkit run: a generic-joints Go2 from its MJCF scores as the quadruped's joints",
          "[cli][generic-joints]") {
  const test::ScratchFolder dir("generic_joints_cli");
  std::string output;
  REQUIRE(runLegkit(dir.path,
                    {"sim", "--scenario", "trot", "--duration", "3", "--seed", "3", "--out",
                     "quadruped.csv"},
                    output) == 0);
  INFO(output);

  // The same rows with the twelve joints as generic columns, joint k = 3 leg + j.
  io::Log log = io::readLog((dir.path / "quadruped.csv").string());
  REQUIRE(log.layout.joints);
  log.layout.joints = false;
  log.layout.torque = false;  // torques belong to the quadruped's joint columns
  log.layout.num_joints = 12;
  for (io::LogRow& row : log.rows) {
    row.joint_q.head<12>() = row.q;
    row.joint_dq.head<12>() = row.dq;
    row.q.setZero();
    row.dq.setZero();
    row.tau.setZero();
  }
  io::writeLog((dir.path / "generic.csv").string(), log);
  std::ofstream(dir.path / "go2.xml")
      << model::quadrupedMjcf(model::QuadrupedGeometry::go2(), model::QuadrupedInertia::go2());
  std::ofstream(dir.path / "robot.yaml")
      << "robot:\n  model: go2.xml\n  base: base\n  feet: [FL_foot, FR_foot, RL_foot, RR_foot]\n";

  const std::vector<std::string> options = {
      "--contact", "truth", "--slip", "none", "--settle", "0", "--no-rolling-foot", "--no-plots"};
  std::vector<std::string> quadruped = {"run", "--log", "quadruped.csv", "--out", "q"};
  std::vector<std::string> generic = {"run",   "--log", "generic.csv", "--config", "robot.yaml",
                                      "--out", "g"};
  quadruped.insert(quadruped.end(), options.begin(), options.end());
  generic.insert(generic.end(), options.begin(), options.end());
  REQUIRE(runLegkit(dir.path, quadruped, output) == 0);
  REQUIRE(runLegkit(dir.path, generic, output) == 0);

  const nlohmann::json q = summary(dir.path / "q").at("estimators");
  const nlohmann::json g = summary(dir.path / "g").at("estimators");
  REQUIRE(q.size() == g.size());
  REQUIRE(q.size() == 6);  // dead reckoning, leg odometry and the four filters
  // MuJoCo's kinematics against the analytic legs: the same foot positions to rounding. The
  // filters carry that to at most 2e-13 relative in any metric (measured); the TSIF's iterated
  // update stops at a tolerance, which turns it into 1.5e-8 (its drift): 1e-10 and 1e-6.
  const auto same = [](const std::string& estimator, double a, double b) {
    const double tolerance = estimator == "tsif" ? 1e-6 : 1e-10;
    return std::abs(a - b) <= tolerance * std::abs(a);
  };
  for (std::size_t i = 0; i < q.size(); ++i) {
    INFO(q[i].at("estimator").get<std::string>());
    CHECK(g[i].at("estimator") == q[i].at("estimator"));
    CHECK(g[i].at("healthy") == true);
    for (const char* key : {"position_rmse_m", "velocity_rmse_mps", "drift_percent",
                            "roll_pitch_rmse_deg", "yaw_rmse_deg", "ate_rmse_m"}) {
      INFO(key << ": quadruped " << q[i].at(key) << ", generic " << g[i].at(key));
      CHECK(same(q[i].at("estimator"), q[i].at(key).get<double>(), g[i].at(key).get<double>()));
    }
  }
  // A foot site the model does not have: refused naming robot.model (exit 2).
  std::ofstream(dir.path / "bad.yaml")
      << "robot:\n  model: go2.xml\n  base: base\n  feet: [FL_foot, FR_foot, RL_foot, XX_foot]\n";
  CHECK(runLegkit(dir.path, {"run", "--log", "generic.csv", "--config", "bad.yaml", "--no-plots"},
                  output) == 2);
  CHECK(output.find("robot.model") != std::string::npos);
}
