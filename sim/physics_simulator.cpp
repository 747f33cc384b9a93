#include "sim/physics_simulator.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>

#include "model/floating_base_dynamics.hpp"
#include "model/mjcf.hpp"
#include "model/mujoco.hpp"
#include "model/quadruped_inertia.hpp"
#include "sim/locomotion_controller.hpp"

namespace legkit::sim {
namespace {

constexpr double kNominalFriction = 0.6;      // friction cone of the naive controller
constexpr double kAwareFriction = 0.08;       // ... and of the friction-aware one
constexpr double kAwareStanceDamping = 30.0;  // the friction-aware stance foot damping [N s/m]
constexpr double kTerrainExtent = 100.0;      // the tiled ground spans +-this in x and y [m]
constexpr double kMaxSlopeAngle = 0.35;       // steepest ramp accepted [rad] (about 20 degrees)
constexpr double kSettleTime = 0.5;           // simulated before the log starts [s]
constexpr double kFootSolmix = 1e6;  // a compliant foot's solref weight against the ground's 1
constexpr double kFallTilt = 1.0;    // |roll| or |pitch| beyond this is a fall [rad]
// No step, ramp or patch edge this close to the starting feet (centres) [m]: the settle and the
// first steps stay on the level ground the robot is placed on (the step-down and slope scenarios'
// edges are 0.41 m ahead of the front feet).
constexpr double kStartClearance = 0.3;
constexpr double kMinPhysicsRate = 500.0, kMaxPhysicsRate = 10000.0;  // accepted range [Hz]
constexpr double kMaxSpeed = 1.5;        // largest commanded |velocity| [m/s]
constexpr double kMaxYawRate = 2.0;      // largest commanded |yaw_rate| [rad/s]
constexpr double kMaxSwingHeight = 0.2;  // highest foot lift [m]

// Independent generator for one purpose (stream) from the user's seed (as sim/simulator.cpp).
std::mt19937_64 stream(unsigned seed, unsigned id) {
  std::seed_seq seq{seed, id, 0x6c65676bu};  // "legk"
  return std::mt19937_64(seq);
}

template <typename T>
[[noreturn]] void bad(const std::string& option, const T& value, const std::string& rule) {
  std::ostringstream os;
  os.precision(17);
  os << "simulatePhysics: " << option << " = " << value << " " << rule;
  throw std::invalid_argument(os.str());
}

void checkFriction(const std::string& option, double mu) {
  if (!(std::isfinite(mu) && mu > 0.0 && mu <= 2.0)) bad(option, mu, "is outside (0, 2]");
}

// Horizontal distance from the point x to the boundary of the patch (inside or out) [m].
double distanceToEdge(const FrictionPatch& p, const Eigen::Vector2d& x) {
  const Eigen::Array2d below = p.min - x, above = x - p.max;
  const Eigen::Array2d outside = below.max(above).max(0.0);
  if ((outside > 0.0).any()) return outside.matrix().norm();
  return (-below).min(-above).minCoeff();  // inside: to the nearest side
}

// The robot starts with its feet on level ground at z = 0 (IK from the scenario's height): no step,
// ramp or patch edge may lie under them or within kStartClearance of them.
void checkStart(const Terrain& terrain, const model::QuadrupedGeometry& g) {
  double front = -kTerrainExtent;  // the foremost starting foot's x [m]
  for (int leg = 0; leg < model::kNumLegs; ++leg) front = std::max(front, g.hip_offset[leg].x());
  const std::string rule =
      "must lie more than 0.3 m ahead of the starting feet (x <= " + std::to_string(front) +
      " m), which stand on level ground at z = 0";
  if (terrain.step_height != 0.0 && !(terrain.step_x > front + kStartClearance)) {
    bad("terrain.step_x", terrain.step_x, rule);
  }
  if (terrain.slope_angle != 0.0 && !(terrain.slope_start > front + kStartClearance)) {
    bad("terrain.slope_start", terrain.slope_start, rule);
  }
  for (const FrictionPatch& p : terrain.patches) {
    for (int leg = 0; leg < model::kNumLegs; ++leg) {
      const Eigen::Vector2d foot(
          g.hip_offset[leg].x(),
          g.hip_offset[leg].y() + model::lateralSign(leg) * g.abduction_offset);
      if (distanceToEdge(p, foot) < kStartClearance) {
        bad("patch min", p.min.transpose(),
            "(and max): the patch edge passes within 0.3 m of the starting " +
                std::string(model::legName(leg)) + " foot");
      }
    }
  }
}

void checkGait(const Gait& gait) {
  if (!(std::isfinite(gait.period) && gait.period > 0.0)) {
    bad("gait.period", gait.period, "must be > 0 s");
  }
  if (!(gait.duty > 0.0 && gait.duty <= 1.0)) bad("gait.duty", gait.duty, "is outside (0, 1]");
  for (double offset : gait.offset) {
    if (!std::isfinite(offset)) bad("gait.offset", offset, "must be finite");
  }
}

void checkOptions(const PhysicsOptions& o, const model::QuadrupedGeometry& geometry) {
  const PhysicsScenario& s = o.scenario;
  if (!(std::isfinite(o.duration) && o.duration > 0.0 && o.duration <= 3600.0)) {
    bad("duration", o.duration, "is outside (0, 3600] s");
  }
  if (!(std::isfinite(o.rate) && o.rate > 0.0)) bad("rate", o.rate, "must be > 0 Hz");
  if (!(o.physics_rate >= kMinPhysicsRate && o.physics_rate <= kMaxPhysicsRate)) {
    bad("physics_rate", o.physics_rate, "is outside [500, 10000] Hz");
  }
  if (std::lround(o.duration * o.rate) < 2) {
    std::ostringstream os;
    os.precision(17);
    os << "s at rate = " << o.rate << " Hz gives fewer than 2 log rows";
    bad("duration", o.duration, os.str());
  }
  const double ratio = o.physics_rate / o.rate;
  if (ratio < 1.0 - 1e-9 || std::abs(ratio - std::round(ratio)) > 1e-9) {
    std::ostringstream os;
    os << "is not a multiple of rate = " << o.rate << " Hz";
    bad("physics_rate", o.physics_rate, os.str());
  }
  const auto nonNegative = [](double x) { return std::isfinite(x) && x >= 0.0; };
  if (!nonNegative(o.encoder_angle_sigma))
    bad("encoder_angle_sigma", o.encoder_angle_sigma, "must be >= 0");
  if (!nonNegative(o.encoder_rate_sigma))
    bad("encoder_rate_sigma", o.encoder_rate_sigma, "must be >= 0");
  if (!nonNegative(o.torque_sigma)) bad("torque_sigma", o.torque_sigma, "must be >= 0");
  if (!nonNegative(o.force_sensor.sigma))
    bad("force_sensor.sigma", o.force_sensor.sigma, "must be >= 0");
  if (!std::isfinite(o.force_sensor.bias))
    bad("force_sensor.bias", o.force_sensor.bias, "must be finite");
  if (!(o.force_sensor.saturation > 0.0)) {
    bad("force_sensor.saturation", o.force_sensor.saturation, "must be > 0");
  }
  const RobotImperfections& r = s.robot;
  if (!(std::isfinite(r.link_length_error) && std::abs(r.link_length_error) <= 0.1)) {
    bad("robot.link_length_error", r.link_length_error, "is outside [-0.1, 0.1]");
  }
  if (!nonNegative(r.joint_offset_sigma))
    bad("robot.joint_offset_sigma", r.joint_offset_sigma, "must be >= 0");
  if (!nonNegative(r.backlash)) bad("robot.backlash", r.backlash, "must be >= 0");
  if (!nonNegative(r.encoder_resolution))
    bad("robot.encoder_resolution", r.encoder_resolution, "must be >= 0");
  if (!(nonNegative(r.encoder_delay) && r.encoder_delay <= 0.1))
    bad("robot.encoder_delay", r.encoder_delay, "is outside [0, 0.1] s");
  if (!(r.imu_rate == 0.0 ||
        (std::isfinite(r.imu_rate) && r.imu_rate > 0.0 && r.imu_rate <= o.rate)))
    bad("robot.imu_rate", r.imu_rate, "must be 0 or in (0, rate]");
  if (!(r.foot_timeconst == 0.0 || (r.foot_timeconst >= 0.002 && r.foot_timeconst <= 0.2)))
    bad("robot.foot_timeconst", r.foot_timeconst, "must be 0 or in [0.002, 0.2] s");
  checkFriction("terrain.friction", s.terrain.friction);
  for (const FrictionPatch& p : s.terrain.patches) {
    checkFriction("patch friction", p.friction);
    if (!p.min.allFinite() || !p.max.allFinite() || (p.min.array() >= p.max.array()).any() ||
        p.min.cwiseAbs().maxCoeff() > kTerrainExtent ||
        p.max.cwiseAbs().maxCoeff() > kTerrainExtent) {
      bad("patch min", p.min.transpose(), "(and max) must satisfy min < max within +-100 m");
    }
  }
  if (!(std::abs(s.terrain.step_height) <= 0.2)) {
    bad("terrain.step_height", s.terrain.step_height, "is outside [-0.2, 0.2] m");
  }
  if (!(std::abs(s.terrain.step_x) < kTerrainExtent)) {
    bad("terrain.step_x", s.terrain.step_x, "is outside (-100, 100) m");
  }
  if (!(std::abs(s.terrain.slope_angle) <= kMaxSlopeAngle)) {
    bad("terrain.slope_angle", s.terrain.slope_angle, "is outside [-0.35, 0.35] rad");
  }
  if (!(s.terrain.slope_length > 0.0)) {
    bad("terrain.slope_length", s.terrain.slope_length, "must be > 0 m");
  }
  if (!(s.terrain.slope_start > -kTerrainExtent &&
        s.terrain.slope_start + s.terrain.slope_length < kTerrainExtent)) {
    bad("terrain.slope_start", s.terrain.slope_start,
        "(to slope_start + slope_length) is outside (-100, 100) m");
  }
  for (const Push& p : s.pushes) {
    if (!p.force.allFinite()) bad("push force", p.force.transpose(), "is not finite");
    if (p.force.norm() > 500.0) bad("push force", p.force.norm(), "N exceeds 500 N");
    if (!nonNegative(p.start) || !nonNegative(p.duration)) {
      bad("push time", p.start, "(start and duration) must be finite and >= 0");
    }
    if (p.start >= o.duration) {
      std::ostringstream os;
      os.precision(17);
      os << "s is not before the end of the run (duration = " << o.duration << " s)";
      bad("push start", p.start, os.str());
    }
  }
  if (!(s.height > 0.15 && s.height < 0.40))
    bad("scenario.height", s.height, "is outside (0.15, 0.40) m");
  if (!(nonNegative(s.stand_time) && nonNegative(s.ramp_duration))) {
    bad("scenario.stand_time", s.stand_time, "(and ramp_duration) must be >= 0");
  }
  if (!(s.velocity.norm() <= kMaxSpeed)) {
    bad("scenario.velocity", s.velocity.transpose(), "has a magnitude outside [0, 1.5] m/s");
  }
  if (!(std::abs(s.yaw_rate) <= kMaxYawRate)) {
    bad("scenario.yaw_rate", s.yaw_rate, "is outside [-2, 2] rad/s");
  }
  if (!(s.swing_height > 0.0 && s.swing_height <= kMaxSwingHeight)) {
    bad("scenario.swing_height", s.swing_height, "is outside (0, 0.2] m");
  }
  checkGait(s.gait);
  checkStart(s.terrain, geometry);
}

// MJCF of the terrain (inside <worldbody>). Flat ground of one friction is the plane alone.
// Otherwise the ground is tiled with boxes, flush with each other: the patch edges, the step and
// the ends of the ramp cut the plane into a grid, each cell gets the friction of the patch over its
// centre (the last one listed) or the ground's, and the ground's surface over it (the 200 m x 200 m
// tiling replaces the plane). Tiling, rather than boxes on the plane, keeps a foot on one surface.
// The ground is a straight line in x over a cell (its kinks are cuts), so each tile is a box
// pitched about y to the cell's grade, its top face exactly that line; on level cells the pitch is
// 0. A pitched tile's lower corners fall under its neighbours' tops, so no edge sticks out.
std::string terrainXml(const Terrain& terrain) {
  if (terrain.patches.empty() && terrain.level()) return {};
  const double thickness = 0.05 + std::abs(terrain.step_height);  // of every tile [m]
  std::vector<double> xs{-kTerrainExtent, kTerrainExtent}, ys{-kTerrainExtent, kTerrainExtent};
  if (terrain.step_height != 0.0) xs.push_back(terrain.step_x);
  if (terrain.slope_angle != 0.0) {
    xs.insert(xs.end(), {terrain.slope_start, terrain.slope_start + terrain.slope_length});
  }
  for (const FrictionPatch& p : terrain.patches) {
    xs.insert(xs.end(), {p.min.x(), p.max.x()});
    ys.insert(ys.end(), {p.min.y(), p.max.y()});
  }
  for (std::vector<double>* cuts : {&xs, &ys}) {
    std::sort(cuts->begin(), cuts->end());
    cuts->erase(std::unique(cuts->begin(), cuts->end()), cuts->end());
  }
  std::ostringstream s;
  s.precision(17);
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    const double cx = 0.5 * (xs[i] + xs[i + 1]);
    const double pitch = std::atan(terrain.grade(cx));  // the tile's top rises at this angle
    const double half_length = 0.5 * (xs[i + 1] - xs[i]) / std::cos(pitch);  // along the top
    // Box centre: half the thickness below the middle of the top face, along the top's normal
    // n = (-sin pitch, 0, cos pitch); MuJoCo's euler (0, -pitch, 0) turns +x up by pitch.
    const double x = cx + 0.5 * thickness * std::sin(pitch);
    const double z = terrain.height(cx) - 0.5 * thickness * std::cos(pitch);
    for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
      const double cy = 0.5 * (ys[j] + ys[j + 1]);
      double mu = terrain.friction;
      for (const FrictionPatch& p : terrain.patches) {
        if (cx > p.min.x() && cx < p.max.x() && cy > p.min.y() && cy < p.max.y()) mu = p.friction;
      }
      s << "<geom name='tile_" << i << '_' << j << "' type='box' pos='" << x << ' ' << cy << ' '
        << z << "' euler='0 " << -pitch << " 0' size='" << half_length << ' '
        << 0.5 * (ys[j + 1] - ys[j]) << ' ' << 0.5 * thickness << "' friction='" << mu
        << " 0.005 0.0001'/>\n";
    }
  }
  return s.str();
}

int id(const mjModel& m, mjtObj type, const std::string& name) {
  const int i = mj_name2id(&m, type, name.c_str());
  if (i < 0) throw std::runtime_error("simulatePhysics: the model has no '" + name + "'");
  return i;
}

// The simulation: MuJoCo model and data, the ids the simulator reads.
struct World {
  model::MjModelPtr m;
  model::MjDataPtr d;
  int base_body;
  int imu_site;
  std::array<int, model::kNumLegs> foot_geom, foot_site, calf_body;
};

World buildWorld(const PhysicsOptions& o, const model::QuadrupedGeometry& geometry,
                 const model::QuadrupedInertia& inertia) {
  const Terrain& terrain = o.scenario.terrain;
  model::MjcfOptions mo;
  mo.timestep = 1.0 / o.physics_rate;
  mo.ground_friction = terrain.friction;
  // MuJoCo takes the larger friction of two touching geoms: with 0 on every robot geom (they never
  // touch each other) the ground's or the patch's friction is the one that acts, however low.
  mo.foot_friction = 0.0;
  mo.extra_worldbody = terrainXml(terrain);
  mo.base_position = {0.0, 0.0, o.scenario.height};
  World w;
  w.m = model::loadMjcf(model::quadrupedMjcf(geometry, inertia, mo));
  mjModel& m = *w.m;
  // With tiles, they are the ground: the plane collides with nothing.
  if (!mo.extra_worldbody.empty()) {
    const int plane = id(m, mjOBJ_GEOM, "ground");
    m.geom_contype[plane] = 0;
    m.geom_conaffinity[plane] = 0;
  }
  w.d = model::makeData(m);
  w.base_body = id(m, mjOBJ_BODY, "base");
  w.imu_site = id(m, mjOBJ_SITE, "imu");
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    const std::string n = model::legName(leg);
    w.foot_geom[leg] = id(m, mjOBJ_GEOM, n + "_foot");
    w.foot_site[leg] = id(m, mjOBJ_SITE, n + "_foot");
    w.calf_body[leg] = id(m, mjOBJ_BODY, n + "_calf");
    // Compliant feet: the foot's solref decides its contacts (MuJoCo mixes two geoms' solref
    // weighted by solmix; the ground keeps 1).
    if (o.scenario.robot.foot_timeconst > 0.0) {
      m.geom_solref[2 * w.foot_geom[leg]] = o.scenario.robot.foot_timeconst;
      m.geom_solmix[w.foot_geom[leg]] = kFootSolmix;
    }
  }
  return w;
}

// The encoders of a real robot (sim/robot_imperfections.hpp): the joints as they were
// encoder_delay ago, through the gear play, off by a constant offset, with white noise, quantised.
class Encoders {
 public:
  Encoders(const PhysicsOptions& o, std::mt19937_64& offset_rng)
      : o_(o), delay_rows_(std::lround(o.scenario.robot.encoder_delay * o.rate)) {
    std::normal_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < io::kNumJoints; ++i) {
      offset_(i) = o.scenario.robot.joint_offset_sigma * unit(offset_rng);
    }
  }

  // Takes the true q, dq of the next row (rows arrive in order).
  void sample(const io::JointVector& q, const io::JointVector& dq) {
    history_.push_back({q, dq});
    if (static_cast<long>(history_.size()) > delay_rows_ + 1) history_.pop_front();
    const io::JointVector& q_then = history_.front().first;  // delay_rows_ ago (row 0 at first)
    if (!played_) played_ = q_then;
    const double half_play = 0.5 * o_.scenario.robot.backlash;
    *played_ = played_->array().max(q_then.array() - half_play).min(q_then.array() + half_play);
  }
  // Joint i's angle and rate readings of that row, given a N(0, 1) draw for its noise (the
  // caller draws them, interleaved with the torques', in the kit's fixed random sequence).
  double angle(int i, double unit_draw) const {
    const double reading = (*played_)(i) + offset_(i) + o_.encoder_angle_sigma * unit_draw;
    const double step = o_.scenario.robot.encoder_resolution;
    return step > 0.0 ? step * std::round(reading / step) : reading;
  }
  double rate(int i, double unit_draw) const {
    return history_.front().second(i) + o_.encoder_rate_sigma * unit_draw;
  }

 private:
  const PhysicsOptions& o_;
  long delay_rows_;
  io::JointVector offset_ = io::JointVector::Zero();
  std::deque<std::pair<io::JointVector, io::JointVector>> history_;
  std::optional<io::JointVector> played_;  // the play operator's output, from the first row
};

// The true state of the base and joints in the controller's terms.
ControllerState trueState(const mjData& d) {
  ControllerState s;
  s.p = Eigen::Map<const Eigen::Vector3d>(d.qpos);
  s.R = Eigen::Quaterniond(d.qpos[3], d.qpos[4], d.qpos[5], d.qpos[6])
            .normalized()
            .toRotationMatrix();
  s.v = Eigen::Map<const Eigen::Vector3d>(d.qvel);
  s.omega = Eigen::Map<const Eigen::Vector3d>(d.qvel + 3);
  s.q = Eigen::Map<const io::JointVector>(d.qpos + 7);
  s.dq = Eigen::Map<const io::JointVector>(d.qvel + 6);
  return s;
}

// Per-foot contact truth at the current (pre-integration) state: forces from mj_contactForce in
// the contact frame (normal, tangent 1, tangent 2), rotated to the world; slip from the velocity
// of the contact point on the foot. qvel is the velocity of that state.
std::array<io::FootTruth, model::kNumLegs> contactTruth(const World& w, const double* qvel,
                                                        double* jac) {
  const mjModel& m = *w.m;
  const mjData& d = *w.d;
  std::array<io::FootTruth, model::kNumLegs> truth{};
  std::array<Eigen::Vector3d, model::kNumLegs> tangential;
  std::array<double, model::kNumLegs> strongest{};
  for (auto& t : tangential) t.setZero();
  const Eigen::Map<const Eigen::VectorXd> v(qvel, m.nv);
  for (int c = 0; c < d.ncon; ++c) {
    const mjContact& con = d.contact[c];
    for (int leg = 0; leg < model::kNumLegs; ++leg) {
      const int g = w.foot_geom[leg];
      if (con.geom1 != g && con.geom2 != g) continue;
      mjtNum f[6];
      mj_contactForce(&m, &d, c, f);
      const Eigen::Map<const Eigen::Matrix<mjtNum, 3, 3, Eigen::RowMajor>> frame(con.frame);
      // frame rows: normal (from geom1 to geom2), tangent 1, tangent 2. The force acts on geom2.
      const double sign = con.geom2 == g ? 1.0 : -1.0;
      const Eigen::Vector3d n = sign * frame.row(0).transpose();
      truth[leg].normal_force += f[0];
      tangential[leg] += sign * (f[1] * frame.row(1).transpose() + f[2] * frame.row(2).transpose());
      if (f[0] > strongest[leg]) {
        strongest[leg] = f[0];
        mj_jac(&m, &d, jac, nullptr, con.pos, w.calf_body[leg]);
        const Eigen::Map<
            const Eigen::Matrix<mjtNum, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
            J(jac, 3, m.nv);
        const Eigen::Vector3d vc = J * v;
        truth[leg].slip_speed = (vc - vc.dot(n) * n).norm();
      }
    }
  }
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    io::FootTruth& t = truth[leg];
    t.normal_force = std::max(t.normal_force, 0.0);
    t.tangential_force = tangential[leg].norm();
    t.contact = t.normal_force > kContactThreshold;
    if (!t.contact) t.slip_speed = 0.0;
    mj_jacSite(&m, &d, jac, nullptr, w.foot_site[leg]);
    const Eigen::Map<const Eigen::Matrix<mjtNum, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
        J(jac, 3, m.nv);
    t.velocity = J * v;
  }
  return truth;
}

// The leg joints' bias forces h (gravity and Coriolis) at the state the controller believes: from
// the kit's own RNEA (model/floating_base_dynamics.hpp), not MuJoCo's, so that the controller sees
// no truth and a wrong estimate reaches its gravity compensation.
io::JointVector legBias(const model::QuadrupedDynamics& dynamics, const ControllerState& s) {
  return dynamics.biasForces(s).tail<io::kNumJoints>();
}

// MuJoCo 2.2.2 answers a non-finite qpos, qvel, qacc or ctrl with a warning and (except for ctrl,
// which it zeroes) by resetting mjData: either way the run is no longer the one asked for. Why, for
// the physics step that started at t, or empty.
std::string divergence(const mjData& d, double t) {
  constexpr std::array<std::pair<int, const char*>, 4> kChecks{{{mjWARN_BADQPOS, "qpos"},
                                                                {mjWARN_BADQVEL, "qvel"},
                                                                {mjWARN_BADQACC, "qacc"},
                                                                {mjWARN_BADCTRL, "ctrl"}}};
  for (const auto& [warning, what] : kChecks) {
    if (d.warning[warning].number == 0) continue;
    std::ostringstream os;
    os << "MuJoCo reset the simulation: bad " << what << " at t = " << t << " s";
    return os.str();
  }
  return {};
}

// Why the robot counts as fallen at this state, or empty.
std::string fallReason(const World& w, const PhysicsScenario& s, const ControllerState& x) {
  const mjModel& m = *w.m;
  const mjData& d = *w.d;
  for (int c = 0; c < d.ncon; ++c) {
    const int b1 = m.geom_bodyid[d.contact[c].geom1], b2 = m.geom_bodyid[d.contact[c].geom2];
    if ((b1 == w.base_body && b2 == 0) || (b2 == w.base_body && b1 == 0)) {
      return "the trunk touched the ground";
    }
  }
  const double roll = std::atan2(x.R(2, 1), x.R(2, 2));
  const double pitch = std::asin(std::clamp(-x.R(2, 0), -1.0, 1.0));
  const double above = x.p.z() - s.terrain.height(x.p.x());
  const bool tilted = std::abs(roll) > kFallTilt || std::abs(pitch) > kFallTilt;
  if (!tilted && above >= 0.5 * s.height) return {};  // the usual case: no string is built
  std::ostringstream os;
  if (std::abs(roll) > kFallTilt) {
    os << "|roll| = " << std::abs(roll) << " rad exceeds 1 rad";
  } else if (std::abs(pitch) > kFallTilt) {
    os << "|pitch| = " << std::abs(pitch) << " rad exceeds 1 rad";
  } else {
    os << "the base is " << above << " m above the ground, below half the height " << s.height
       << " m";
  }
  return os.str();
}

}  // namespace

PhysicsOptions PhysicsOptions::forScenario(const std::string& name) {
  PhysicsOptions o;
  o.scenario = physicsScenarioByName(name);
  o.duration = o.scenario.duration;
  return o;
}

PhysicsOptions& PhysicsOptions::noiseless() {
  imu_noise = model::ImuNoise::noiseless();
  initial_bias = model::ImuBias{};
  encoder_angle_sigma = 0.0;
  encoder_rate_sigma = 0.0;
  torque_sigma = 0.0;
  force_sensor.sigma = 0.0;
  force_sensor.bias = 0.0;
  return *this;
}

PhysicsResult simulatePhysics(const PhysicsOptions& o) {
  const PhysicsScenario& scenario = o.scenario;
  // The robot as built: its links (1 + link_length_error) times the model's the estimators use.
  model::QuadrupedGeometry geometry = model::QuadrupedGeometry::go2();
  geometry.thigh_length *= 1.0 + scenario.robot.link_length_error;
  geometry.calf_length *= 1.0 + scenario.robot.link_length_error;
  checkOptions(o, geometry);
  const model::QuadrupedInertia inertia = model::QuadrupedInertia::go2();
  const model::QuadrupedKinematics kinematics(geometry);
  const model::QuadrupedDynamics dynamics(geometry, inertia);
  World w = buildWorld(o, geometry, inertia);
  mjModel& m = *w.m;
  mjData& d = *w.d;

  // Start standing still, feet under the hips on the ground (IK).
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    const Eigen::Vector3d foot(
        geometry.hip_offset[leg].x(),
        geometry.hip_offset[leg].y() + model::lateralSign(leg) * geometry.abduction_offset,
        geometry.foot_radius - scenario.height);
    const Eigen::Vector3d q = kinematics.inverseKinematics(leg, foot);
    Eigen::Map<Eigen::Vector3d>(d.qpos + 7 + std::size_t{io::kJointsPerLeg} * leg) = q;
  }
  mj_forward(&m, &d);

  LocomotionCommand command;
  command.gait = scenario.gait;
  command.gait.start = scenario.stand_time;
  command.velocity = scenario.velocity;
  command.yaw_rate = scenario.yaw_rate;
  command.height = scenario.height;
  command.swing_height = scenario.swing_height;
  command.ramp_duration = scenario.ramp_duration;
  command.mu_assumed = scenario.friction_aware ? kAwareFriction : kNominalFriction;
  ControllerGains gains;
  if (scenario.friction_aware) gains.kd_stance = kAwareStanceDamping;
  LocomotionController controller(kinematics, inertia.totalMass(), command, trueState(d), gains);

  PhysicsResult out;
  // Settle: the feet start exactly touching the ground, carrying nothing; let the contacts take
  // the weight before the log starts at t = 0 (controller only, nothing logged).
  d.time = -kSettleTime;
  while (d.time < -0.5 / o.physics_rate) {
    const double t = d.time;
    mj_step1(&m, &d);
    const ControllerState x = trueState(d);
    Eigen::Map<io::JointVector>(d.ctrl) = controller.torques(t, x, legBias(dynamics, x));
    mj_step2(&m, &d);
    const std::string reason = divergence(d, t);
    if (!reason.empty()) {
      out.status = {true, t, reason, true};
      return out;
    }
  }
  d.time = 0.0;

  std::mt19937_64 imu_rng = stream(o.seed, 1);
  std::mt19937_64 encoder_rng = stream(o.seed, 2);
  std::mt19937_64 torque_rng = stream(o.seed, 4);
  std::mt19937_64 force_rng = stream(o.seed, 5);
  std::mt19937_64 offset_rng = stream(o.seed, 6);
  std::normal_distribution<double> unit(0.0, 1.0);
  Encoders encoders(o, offset_rng);
  const double imu_rate = scenario.robot.imu_rate;
  model::ImuReading imu_held;  // the IMU's last sample, held until its next
  long imu_samples = 0;

  io::Log& log = out.log;
  log.layout.joints = true;
  log.layout.torque = true;
  log.layout.force = true;
  log.layout.contact = true;
  log.layout.ground_truth = o.ground_truth;
  log.layout.contact_truth = o.ground_truth;
  std::ostringstream about;
  about.precision(17);
  about << "legkit sim (physics, MuJoCo " << mj_versionString() << "): scenario " << scenario.name
        << ", duration " << o.duration << " s, rate " << o.rate << " Hz, physics " << o.physics_rate
        << " Hz, seed " << o.seed << (o.closed_loop ? ", closed loop" : "");
  log.comments.push_back(about.str());

  const double dt = 1.0 / o.rate;
  const int substeps = static_cast<int>(std::lround(o.physics_rate / o.rate));
  const long n = std::lround(o.duration * o.rate);
  log.rows.reserve(n);
  out.bias.reserve(n);
  std::vector<mjtNum> jac(std::size_t{3} * m.nv);
  mjtNum* const push = d.xfrc_applied + std::size_t{6} * w.base_body;  // force, torque on the trunk
  model::ImuBias bias = o.initial_bias;
  bool estimated = false;
  BaseEstimate estimate;
  io::LogRow sensed;  // the last row: the closed-loop controller's gyro and encoders
  const double t_track = scenario.stand_time + scenario.ramp_duration;
  double sq_error = 0.0, yaw_rate_sum = 0.0;
  Eigen::Vector2d v_sum = Eigen::Vector2d::Zero();
  long tracked = 0;

  for (long k = 0; k < n; ++k) {
    io::LogRow row;
    row.t = k * dt;
    ControllerState now;
    Eigen::Matrix<double, io::kNumJoints, 1> applied;
    std::array<io::FootTruth, model::kNumLegs> truth{};
    Eigen::Vector3d omega_sum = Eigen::Vector3d::Zero();
    for (int j = 0; j < substeps; ++j) {
      const double t = d.time;
      mj_step1(&m, &d);
      const ControllerState x = trueState(d);
      ControllerState view = x;
      if (estimated) {
        view.R = estimate.R;
        view.p = estimate.p;
        view.v = estimate.v;
        view.omega = sensed.gyro;
        view.q = sensed.q;
        view.dq = sensed.dq;
      }
      Eigen::Map<io::JointVector>(d.ctrl) = controller.torques(t, view, legBias(dynamics, view));
      mju_zero(push, 6);
      for (const Push& p : scenario.pushes) {
        if (t >= p.start && t < p.start + p.duration) Eigen::Map<Eigen::Vector3d>(push) += p.force;
      }
      mj_step2(&m, &d);
      const std::string diverged = divergence(d, t);
      if (!diverged.empty()) {
        out.status = {true, t, diverged, true};
        break;
      }
      if (j == 0) {
        now = x;
        applied = Eigen::Map<const io::JointVector>(d.actuator_force);
        // The contacts and the kinematics are still those of the state x (before integration).
        Eigen::Matrix<double, 18, 1> qvel;
        qvel.head<3>() = x.v;
        qvel.segment<3>(3) = x.omega;
        qvel.tail<12>() = x.dq;
        truth = contactTruth(w, qvel.data(), jac.data());
        const std::string reason = fallReason(w, scenario, x);
        if (!reason.empty()) {
          out.status = {true, row.t, reason, false};
          break;
        }
      }
      omega_sum += Eigen::Map<const Eigen::Vector3d>(d.qvel + 3);  // the rate the step applied
    }
    if (out.status.fell) break;

    // IMU: mean rate and mean world acceleration over [t_k, t_k + dt).
    const Eigen::Vector3d a = (Eigen::Map<const Eigen::Vector3d>(d.qvel) - now.v) / dt;
    const model::ImuBias bias_now = bias;
    const model::ImuReading imu =
        model::synthesiseReading(o.imu_noise, dt, now.R, a, omega_sum / substeps, bias, imu_rng);
    if (imu_rate == 0.0 || row.t >= imu_samples / imu_rate - 0.5 * dt) {
      imu_held = imu;  // a fresh sample
      ++imu_samples;
    }
    row.gyro = imu_held.w_m;
    row.acc = imu_held.a_m;
    encoders.sample(now.q, now.dq);
    for (int i = 0; i < io::kNumJoints; ++i) {
      row.q(i) = encoders.angle(i, unit(encoder_rng));
      row.dq(i) = encoders.rate(i, unit(encoder_rng));
      row.tau(i) = applied(i) + o.torque_sigma * unit(torque_rng);
    }
    for (int leg = 0; leg < model::kNumLegs; ++leg) {
      const double reading =
          truth[leg].normal_force + o.force_sensor.bias + o.force_sensor.sigma * unit(force_rng);
      row.force[leg] = std::clamp(reading, 0.0, o.force_sensor.saturation);
      row.contact[leg] = truth[leg].contact;
      if (o.ground_truth) row.gt_feet[leg] = truth[leg];
    }
    if (o.ground_truth) {
      row.gt_p = now.p;
      row.gt_q = Eigen::Quaterniond(now.R).normalized();
      row.gt_v = now.v;
    }

    if (row.t >= t_track) {
      const Eigen::Matrix3d H =
          Eigen::AngleAxisd(std::atan2(now.R(1, 0), now.R(0, 0)), Eigen::Vector3d::UnitZ())
              .toRotationMatrix();
      const Eigen::Vector3d v_cmd =
          H * Eigen::Vector3d(scenario.velocity.x(), scenario.velocity.y(), 0.0);
      sq_error += (now.v - v_cmd).head<2>().squaredNorm();
      v_sum += (H.transpose() * now.v).head<2>();
      yaw_rate_sum += (now.R * now.omega).z();
      ++tracked;
    }
    out.max_tilt = std::max(out.max_tilt, std::acos(std::clamp(now.R(2, 2), -1.0, 1.0)));

    log.rows.push_back(row);
    out.bias.push_back(bias_now);
    if (o.closed_loop) {
      sensed = row;
      estimated = o.closed_loop->update(row, estimate) || estimated;
    }
  }
  if (tracked > 0) {
    out.velocity_rmse = std::sqrt(sq_error / tracked);
    out.mean_velocity = v_sum / tracked;
    out.mean_yaw_rate = yaw_rate_sum / tracked;
  }
  return out;
}

}  // namespace legkit::sim
