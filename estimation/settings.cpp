#include "estimation/settings.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "estimation/estimators.hpp"
#include "io/yaml_reader.hpp"

namespace legkit {
namespace {

constexpr double kPi = 3.14159265358979323846;

// ---- values as YAML text -------------------------------------------------------------------

std::string formatNumber(double x) {
  char buffer[32];  // the shortest text that reads back to the same double
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, x);
  if (ec != std::errc()) throw std::logic_error("settingsYaml: a number that does not print");
  return std::string(buffer, end);
}

// A YAML double-quoted scalar that yaml-cpp reads back as exactly `s`: '"' and '\' escaped, and
// every control character (a raw newline would fold to a space, a raw NUL or tab would change or
// end the name) as an escape. The reader refuses control characters in names (io::YamlValue::text,
// file:line:key), so a name that has one is written as it is and refused when read, never read
// back changed. Bytes from 0x80 up (UTF-8) are written as they are: "\xNN" would mean U+00NN.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\r') {
      out += "\\r";
    } else if (u < 0x20 || u == 0x7f) {
      const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[u >> 4];
      out += hex[u & 0xf];
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string flowList(const std::vector<std::string>& items) {
  std::string out = "[";
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out + "]";
}

// ---- the schema: every key once, with how it is read, how it is written and what it means ----

// A key (read and write set) or a section (children set). A key without write is read only: an
// alternative spelling of another key.
struct Node {
  using Reader = std::function<void(Settings&, const io::YamlValue&)>;
  using Writer = std::function<std::string(const Settings&)>;  // the value as one line of YAML
  // A check across the keys of a section, after they are read (the section's value for errors).
  using Check = std::function<void(const Settings&, const io::YamlValue&)>;
  Node(std::string key_, std::string comment_, Reader read_, Writer write_,
       std::vector<Node> children_ = {}, Check check_ = nullptr)
      : key(std::move(key_)),
        comment(std::move(comment_)),
        read(std::move(read_)),
        write(std::move(write_)),
        children(std::move(children_)),
        check(std::move(check_)) {}

  std::string key;
  std::string comment;  // meaning and unit
  Reader read;
  Writer write;
  std::vector<Node> children;
  Check check;
};

template <class T>
using Ref = T& (*)(Settings&);
// The writers read through the same accessor as the readers; they never modify.
template <class T>
const T& get(Ref<T> ref, const Settings& s) {
  return ref(const_cast<Settings&>(s));
}

Node number(const std::string& key, Ref<double> ref, double lo, double hi,
            const std::string& comment) {
  return {key, comment, [=](Settings& s, const io::YamlValue& v) { ref(s) = v.number(lo, hi); },
          [=](const Settings& s) { return formatNumber(get(ref, s)); }};
}

// A number in (0, hi]: zero is refused here, where the file and line are known.
Node positive(const std::string& key, Ref<double> ref, double hi, const std::string& comment) {
  return {key, comment,
          [=](Settings& s, const io::YamlValue& v) {
            const double x = v.number(0, hi);
            if (x == 0) {
              v.fail("expected a number in (0, " + formatNumber(hi) +
                     "], got 0 (the filters need some white noise)");
            }
            ref(s) = x;
          },
          [=](const Settings& s) { return formatNumber(get(ref, s)); }};
}

// A number, or `auto` (unset) for a value the run derives from the robot.
Node numberOrAuto(const std::string& key, Ref<std::optional<double>> ref, double lo, double hi,
                  const std::string& comment) {
  return {key, comment,
          [=](Settings& s, const io::YamlValue& v) {
            if (!v.isMap() && !v.isList() && !v.isNull() && v.text() == "auto") {
              ref(s).reset();
            } else {
              ref(s) = v.number(lo, hi);
            }
          },
          [=](const Settings& s) {
            const std::optional<double>& x = get(ref, s);
            return x ? formatNumber(*x) : std::string("auto");
          }};
}

Node integer(const std::string& key, Ref<int> ref, int lo, int hi, const std::string& comment) {
  return {key, comment, [=](Settings& s, const io::YamlValue& v) { ref(s) = v.integer(lo, hi); },
          [=](const Settings& s) { return std::to_string(get(ref, s)); }};
}

Node flag(const std::string& key, Ref<bool> ref, const std::string& comment) {
  return {key, comment, [=](Settings& s, const io::YamlValue& v) { ref(s) = v.boolean(); },
          [=](const Settings& s) { return std::string(get(ref, s) ? "true" : "false"); }};
}

Node text(const std::string& key, Ref<std::string> ref, const std::string& comment) {
  return {key, comment, [=](Settings& s, const io::YamlValue& v) { ref(s) = v.text(); },
          [=](const Settings& s) { return quoted(get(ref, s)); }};
}

// A list of names; `allowed` (when given) is what each may be, and none may repeat.
Node names(const std::string& key, Ref<std::vector<std::string>> ref,
           std::function<std::vector<std::string>()> allowed, const std::string& comment) {
  return {key, comment,
          [=](Settings& s, const io::YamlValue& v) {
            std::vector<std::string> out;
            for (const io::YamlValue& e : v.elements()) {
              const std::string name = allowed ? e.oneOf(allowed()) : e.text();
              if (name.empty()) e.fail("expected a name, got an empty one");
              if (std::find(out.begin(), out.end(), name) != out.end()) {
                e.fail("'" + name + "' is listed twice");
              }
              out.push_back(name);
            }
            ref(s) = out;
          },
          [=](const Settings& s) {
            std::vector<std::string> items;
            for (const std::string& n : get(ref, s)) items.push_back(quoted(n));
            return flowList(items);
          }};
}

Node vector3(const std::string& key, Ref<Eigen::Vector3d> ref, double lo, double hi,
             const std::string& comment) {
  return {key, comment,
          [=](Settings& s, const io::YamlValue& v) {
            const std::vector<io::YamlValue> e = v.elements(3);
            ref(s) = {e[0].number(lo, hi), e[1].number(lo, hi), e[2].number(lo, hi)};
          },
          [=](const Settings& s) {
            const Eigen::Vector3d& x = get(ref, s);
            return flowList({formatNumber(x.x()), formatNumber(x.y()), formatNumber(x.z())});
          }};
}

// A list of numbers, each in [lo, hi).
Node numbers(const std::string& key, Ref<std::vector<double>> ref, double lo, double hi,
             const std::string& comment) {
  return {key, comment,
          [=](Settings& s, const io::YamlValue& v) {
            std::vector<double> out;
            for (const io::YamlValue& e : v.elements()) {
              const double x = e.number(lo, hi);
              if (x == hi)
                e.fail("expected a number in [" + formatNumber(lo) + ", " + formatNumber(hi) +
                       "), got " + formatNumber(x));
              out.push_back(x);
            }
            ref(s) = out;
          },
          [=](const Settings& s) {
            std::vector<std::string> items;
            for (const double x : get(ref, s)) items.push_back(formatNumber(x));
            return flowList(items);
          }};
}

// An enum as one of its names.
template <class E>
Node choice(const std::string& key, Ref<E> ref, std::vector<std::pair<E, std::string>> table,
            const std::string& comment) {
  std::vector<std::string> allowed;
  for (const auto& [value, name] : table) allowed.push_back(name);
  return {key, comment,
          [=](Settings& s, const io::YamlValue& v) {
            const std::string name = v.oneOf(allowed);
            for (const auto& [value, n] : table) {
              if (n == name) ref(s) = value;
            }
          },
          [=](const Settings& s) {
            for (const auto& [value, name] : table) {
              if (value == get(ref, s)) return quoted(name);
            }
            throw std::logic_error("settingsYaml: " + key + " has no name");
          }};
}

Node section(const std::string& key, const std::string& comment, std::vector<Node> children,
             std::function<void(const Settings&, const io::YamlValue&)> check = nullptr) {
  Node n{key, comment, nullptr, nullptr, std::move(children), std::move(check)};
  return n;
}

// The quaternion R_BI as [w, x, y, z]: a unit quaternion up to rounding (1e-4) is normalised; one
// already of unit norm to the last bits is kept as written, so that a file reads back exactly.
Node rotationWxyz() {
  return {"rotation",
          "R_BI, IMU axes to base axes, as a quaternion [w, x, y, z] (or give rotation_rpy_deg: "
          "[roll, pitch, yaw] in degrees, R = Rz(yaw) Ry(pitch) Rx(roll), instead)",
          [](Settings& s, const io::YamlValue& v) {
            const std::vector<io::YamlValue> e = v.elements(4);
            Eigen::Quaterniond q(e[0].number(-1, 1), e[1].number(-1, 1), e[2].number(-1, 1),
                                 e[3].number(-1, 1));
            const double norm = q.norm();
            if (std::abs(norm - 1.0) > 1e-4) {
              v.fail("expected a unit quaternion [w, x, y, z], got norm " + formatNumber(norm));
            }
            if (std::abs(norm - 1.0) > 4 * std::numeric_limits<double>::epsilon()) q.normalize();
            s.imu_extrinsic.q_BI = q;
          },
          [](const Settings& s) {
            const Eigen::Quaterniond& q = s.imu_extrinsic.q_BI;
            return flowList({formatNumber(q.w()), formatNumber(q.x()), formatNumber(q.y()),
                             formatNumber(q.z())});
          }};
}

Node rotationRpy() {
  return {"rotation_rpy_deg", "",
          [](Settings& s, const io::YamlValue& v) {
            const std::vector<io::YamlValue> e = v.elements(3);
            const double deg = kPi / 180.0;
            const double roll = e[0].number(-180, 180) * deg;
            const double pitch = e[1].number(-90, 90) * deg;
            const double yaw = e[2].number(-180, 180) * deg;
            s.imu_extrinsic.q_BI = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                   Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                   Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
          },
          nullptr};
}

std::vector<std::string> contactSources() {
  std::vector<std::string> all = {"truth"};
  for (const std::string& name : contact::detectorNames()) all.push_back(name);
  return all;
}

const std::vector<Node>& schema() {
  using S = Settings;
  static const std::vector<Node> root = {
      section(
          "imu", "The IMU: continuous noise densities (datasheet, or `legkit allan`) and its pose",
          {positive(
               "gyro_noise_density", [](S& s) -> double& { return s.imu.gyro_noise_density; },
               model::ImuNoiseLimits::gyro_noise_density,
               "sigma_g, gyro white noise [rad/s/sqrt(Hz)]"),
           positive(
               "accel_noise_density", [](S& s) -> double& { return s.imu.accel_noise_density; },
               model::ImuNoiseLimits::accel_noise_density,
               "sigma_a, accelerometer white noise [m/s^2/sqrt(Hz)]"),
           number(
               "gyro_bias_random_walk", [](S& s) -> double& { return s.imu.gyro_bias_random_walk; },
               0, model::ImuNoiseLimits::gyro_bias_random_walk,
               "sigma_bg, gyro bias random walk [rad/s^2/sqrt(Hz)]"),
           number(
               "accel_bias_random_walk",
               [](S& s) -> double& { return s.imu.accel_bias_random_walk; }, 0,
               model::ImuNoiseLimits::accel_bias_random_walk,
               "sigma_ba, accelerometer bias random walk [m/s^3/sqrt(Hz)]"),
           section(
               "extrinsic", "The IMU's pose in the base frame, T_BI (identity: base = IMU)",
               {rotationWxyz(), rotationRpy(),
                vector3(
                    "translation", [](S& s) -> Eigen::Vector3d& { return s.imu_extrinsic.p_BI; },
                    -10, 10, "p_BI, the IMU's origin in the base frame [m]")},
               [](const Settings&, const io::YamlValue& v) {
                 if (v.find("rotation") && v.find("rotation_rpy_deg")) {
                   v.fail("give rotation or rotation_rpy_deg, not both");
                 }
               })}),
      section("limits", "What a sensor can physically report; beyond it a sample is not used",
              {number(
                   "gyro_max", [](S& s) -> double& { return s.limits.gyro_max; }, 0.1, 1000,
                   "gyro range per axis [rad/s]"),
               number(
                   "accel_max", [](S& s) -> double& { return s.limits.accel_max; }, 1, 10000,
                   "accelerometer range per axis [m/s^2]"),
               number(
                   "max_dt", [](S& s) -> double& { return s.limits.max_dt; }, 1e-4, 10,
                   "a longer step between samples is a gap, not integrated [s]"),
               number(
                   "foot_distance_max", [](S& s) -> double& { return s.limits.foot_distance_max; },
                   0.01, 100, "|p_body| of a stance foot, longer than any leg [m]"),
               number(
                   "foot_variance_max", [](S& s) -> double& { return s.limits.foot_variance_max; },
                   1e-6, 1e12, "largest foot-position variance per axis used [m^2]"),
               number(
                   "foot_speed_max", [](S& s) -> double& { return s.limits.foot_speed_max; }, 0.01,
                   1000, "|v_body| of a stance foot [m/s]"),
               number(
                   "speed_max", [](S& s) -> double& { return s.limits.speed_max; }, 0.1, 10000,
                   "an estimate faster than this is not a robot's: the filter recovers [m/s]"),
               number(
                   "position_max", [](S& s) -> double& { return s.limits.position_max; }, 1, 1e9,
                   "an estimate farther from the origin: the filter recovers [m]")}),
      section(
          "priors", "The filters' prior at reset, standard deviations per axis",
          {number(
               "sigma_attitude", [](S& s) -> double& { return s.priors.sigma_attitude; }, 1e-6, kPi,
               "attitude (ESKF, InEKF, TSIF) [rad]"),
           number(
               "sigma_velocity", [](S& s) -> double& { return s.priors.sigma_velocity; }, 1e-6, 100,
               "velocity [m/s]"),
           number(
               "sigma_position", [](S& s) -> double& { return s.priors.sigma_position; }, 1e-6, 1e4,
               "position [m]"),
           number(
               "sigma_gyro_bias", [](S& s) -> double& { return s.priors.sigma_gyro_bias; }, 1e-9, 1,
               "gyro bias (also the linear KF's attitude filter) [rad/s]"),
           number(
               "sigma_accel_bias", [](S& s) -> double& { return s.priors.sigma_accel_bias; }, 1e-9,
               10, "accelerometer bias (ESKF, InEKF, TSIF) [m/s^2]"),
           number(
               "foot_init_sigma", [](S& s) -> double& { return s.priors.foot_init_sigma; }, 1e-6,
               1000,
               "a foot state before its first stance measurement (ESKF, TSIF, linear KF) [m]")}),
      section(
          "feet", "The feet's random walks in the ESKF, the InEKF and the TSIF",
          {number(
               "stance_density", [](S& s) -> double& { return s.feet.stance_density; }, 1e-9, 1,
               "a stance foot's slip allowance (also the linear KF's) [m/sqrt(s)]"),
           number(
               "swing_density", [](S& s) -> double& { return s.feet.swing_density; }, 1e-6, 100,
               "a swing foot, the p_c = 0 end of a soft contact [m/sqrt(s)]"),
           flag(
               "correct_yaw", [](S& s) -> bool& { return s.feet.correct_yaw; },
               "stance feet may correct the heading (yaw and the gyro bias about the "
               "vertical), which they cannot observe: false keeps the gyro's heading (the "
               "heading rule of section 57.5)"),
           number(
               "heading_turn_rate", [](S& s) -> double& { return s.feet.heading_turn_rate; }, 0, 10,
               "the yaw rate from which no stance foot corrects the heading (the heading "
               "rule); below it the feet may, in proportion, so that they learn the "
               "vertical gyro bias while the robot walks straight; 0: never (section 57.5) "
               "[rad/s]"),
           number(
               "heading_turn_time", [](S& s) -> double& { return s.feet.heading_turn_time; }, 1e-3,
               100,
               "the low-pass of that yaw rate, and how long the feet leave the heading "
               "alone after a slip [s]"),
           flag(
               "flat", [](S& s) -> bool& { return s.feet.flat; },
               "flat feet (a humanoid's soles): the ESKF, the InEKF and the TSIF also use each "
               "stance foot's orientation from the robot's model (at most two feet; section "
               "57.5)"),
           number(
               "rotation_stance_density",
               [](S& s) -> double& { return s.feet.rotation_stance_density; }, 1e-9, 1,
               "a flat stance foot's rotation random walk [rad/sqrt(s)]")}),
      section(
          "linear_kf", "The linear KF of section 57.4 and its attitude filter",
          {number(
               "foot_swing_density", [](S& s) -> double& { return s.linear_kf.foot_swing_density; },
               1e-6, 100, "a swing foot's random walk [m/sqrt(s)]"),
           flag(
               "use_leg_velocity", [](S& s) -> bool& { return s.linear_kf.use_leg_velocity; },
               "fuse the leg-odometry velocity measurement"),
           number(
               "foot_velocity_sigma",
               [](S& s) -> double& { return s.linear_kf.foot_velocity_sigma; }, 1e-6, 10,
               "noise of the body-frame foot velocity r_dot per axis [m/s]"),
           flag(
               "model_attitude_error",
               [](S& s) -> bool& { return s.linear_kf.model_attitude_error; },
               "account for the attitude filter's error in Q and R"),
           number(
               "attitude_correlation_time",
               [](S& s) -> double& { return s.linear_kf.attitude_correlation_time; }, 1e-3, 1000,
               "tau of the attitude error, about 1 / k_P [s]"),
           number(
               "accel_compensation_time",
               [](S& s) -> double& { return s.linear_kf.accel_compensation_time; }, 0, 10,
               "low-pass of the base acceleration given to the attitude filter, 0: none [s]"),
           number(
               "k_P", [](S& s) -> double& { return s.linear_kf.k_P; }, 0, 100,
               "attitude filter tilt-correction bandwidth [rad/s]"),
           number(
               "k_I", [](S& s) -> double& { return s.linear_kf.k_I; }, 0, 100,
               "attitude filter gyro-bias gain [1/s^2]"),
           number(
               "accel_tolerance", [](S& s) -> double& { return s.linear_kf.accel_tolerance; }, 1e-3,
               10, "the tilt correction's trust is 0 when | |a_m|/g - 1 | reaches this [-]"),
           number(
               "sigma_tilt", [](S& s) -> double& { return s.linear_kf.sigma_tilt; }, 0, kPi,
               "attitude filter prior, roll and pitch [rad]"),
           number(
               "sigma_yaw", [](S& s) -> double& { return s.linear_kf.sigma_yaw; }, 0, kPi,
               "attitude filter prior, yaw [rad]")}),
      section("invariant_ekf", "The invariant EKF of section 57.5",
              {choice<invariant::inekf::Discretisation>(
                   "discretisation",
                   [](S& s) -> invariant::inekf::Discretisation& {
                     return s.invariant_ekf.discretisation;
                   },
                   {{invariant::inekf::Discretisation::kExact, "exact"},
                    {invariant::inekf::Discretisation::kFirstOrder, "first-order"}},
                   "exact: closed-form Phi; first-order: Phi = I + A dt, the reference "
                   "implementation's"),
               choice<invariant::inekf::TouchdownAttitude>(
                   "touchdown_attitude",
                   [](S& s) -> invariant::inekf::
                                TouchdownAttitude& { return s.invariant_ekf.touchdown_attitude; },
                   {{invariant::inekf::TouchdownAttitude::kCorrected, "corrected"},
                    {invariant::inekf::TouchdownAttitude::kPredicted, "predicted"}},
                   "the attitude that places a new foot: after this sample's correction, or "
                   "before it (the reference's)")}),
      section("tsif", "The two-state implicit filter",
              {integer(
                  "iterations", [](S& s) -> int& { return s.tsif.iterations; }, 1, 2,
                  "Gauss-Newton iterations per step")}),
      section("frontend", "The leg measurements' noise (the front end: joints to feet)",
              {number(
                   "encoder_angle_sigma",
                   [](S& s) -> double& { return s.frontend.encoder_angle_sigma; }, 0, 0.1,
                   "joint encoder noise [rad]"),
               number(
                   "foot_point_sigma", [](S& s) -> double& { return s.frontend.foot_point_sigma; },
                   0, 0.1, "the contact point on a round foot [m]"),
               number(
                   "foot_rotation_sigma",
                   [](S& s) -> double& { return s.frontend.foot_rotation_sigma; }, 0, 0.5,
                   "a flat foot's orientation against the ground, beyond the encoders (feet.flat) "
                   "[rad]"),
               choice<StampHandling>(
                   "timestamps", [](S& s) -> StampHandling& { return s.conditioning.stamps; },
                   {{StampHandling::kAuto, "auto"},
                    {StampHandling::kLogged, "logged"},
                    {StampHandling::kSmoothed, "smoothed"}},
                   "a recorded log's stamps: smoothed (a line fitted over 21 rows), logged, or "
                   "auto: smoothed when the row interval jitters by more than 10 %"),
               choice<JointVelocitySource>(
                   "joint_velocities",
                   [](S& s) -> JointVelocitySource& { return s.conditioning.joint_velocities; },
                   {{JointVelocitySource::kAuto, "auto"},
                    {JointVelocitySource::kLogged, "logged"},
                    {JointVelocitySource::kAngles, "angles"}},
                   "a recorded log's joint velocities: as logged, the angles' backward difference, "
                   "or auto: as logged, from the angles when the log has no velocity columns"),
               number(
                   "truth_velocity_window", [](S& s) -> double& { return s.truth_velocity_window; },
                   1e-3, 1,
                   "a pose-only truth's velocity: the central difference over this window, for the "
                   "metrics, the NEES and the initial state [s]")}),
      section(
          "robot", "The robot whose legs the log's joints describe",
          {text(
               "model", [](S& s) -> std::string& { return s.robot.model; },
               "\"\": the built-in Go2-class quadruped; else a URDF or MJCF file (relative: to "
               "this file's folder)"),
           text(
               "base", [](S& s) -> std::string& { return s.robot.base; },
               "the base body's name in that model"),
           names(
               "feet", [](S& s) -> std::vector<std::string>& { return s.robot.feet; }, nullptr,
               "foot frames (sites or bodies), in foot-id order"),
           names(
               "joints", [](S& s) -> std::vector<std::string>& { return s.robot.joints; }, nullptr,
               "model joints in the log's joint<k>_ column order ([]: the hinges in order)"),
           number(
               "mass", [](S& s) -> double& { return s.robot.mass; }, 0, 1e4,
               "the robot's mass, which scales the contact force thresholds; 0: the model's (the "
               "sum of its bodies'), the built-in Go2's 15.2 kg without a model [kg]")},
          [](const Settings& s, const io::YamlValue& v) {
            if (!s.robot.model.empty() && (s.robot.base.empty() || s.robot.feet.empty())) {
              v.fail("a robot model needs its base body and its feet");
            }
            const std::pair<const char*, bool> named[] = {{"base", !s.robot.base.empty()},
                                                          {"feet", !s.robot.feet.empty()},
                                                          {"joints", !s.robot.joints.empty()}};
            for (const auto& [key, given] : named) {
              const std::optional<io::YamlValue> value = v.find(key);
              if (s.robot.model.empty() && given && value) {
                value->fail(
                    "given without robot.model (it names part of that model; the "
                    "built-in Go2 has its own)");
              }
            }
          }),
      names(
          "estimators", [](S& s) -> std::vector<std::string>& { return s.estimators; },
          estimatorNames, "which estimators run, in this order ([]: every one)"),
      section(
          "contact", "Where stance comes from and what happens to it before the filters",
          {text(
               "detector", [](S& s) -> std::string& { return s.pipeline.contact; },
               "\"truth\" (the log's contact flags) or a detector: " +
                   flowList(contact::detectorNames())),
           flag(
               "rolling_foot", [](S& s) -> bool& { return s.pipeline.rolling_foot; },
               "the stance point on the ground, not the foot sphere's centre"),
           number(
               "settle_time", [](S& s) -> double& { return s.pipeline.settle_time; }, 0, 1,
               "touchdown settling: a foot just put down is left out this long, 0: off [s]"),
           number(
               "no_contact_bound", [](S& s) -> double& { return s.pipeline.no_contact_bound; },
               1e-3, 100, "longest stretch without a stance foot before it is reported [s]"),
           choice<slip::SlipReaction>(
               "slip_reaction", [](S& s) -> slip::SlipReaction& { return s.pipeline.slip; },
               {{slip::SlipReaction::kNone, "none"},
                {slip::SlipReaction::kInflate, "inflate"},
                {slip::SlipReaction::kDrop, "drop"},
                {slip::SlipReaction::kImuOnly, "imu-only"}},
               "what the filters do with a foot found slipping"),
           section("soft", "How a detector's contact probability p_c weights a foot",
                   {number(
                        "eps", [](S& s) -> double& { return s.pipeline.soft.eps; }, 1e-6, 1,
                        "R / (p_c + eps): keeps R finite at p_c = 0 [-]"),
                    number(
                        "swing_sigma", [](S& s) -> double& { return s.pipeline.soft.swing_sigma; },
                        0, 10, "position noise of a foot not on the ground [m]"),
                    number(
                        "min_probability",
                        [](S& s) -> double& { return s.pipeline.soft.min_probability; }, 0, 1,
                        "feet below this p_c are not handed to the filters [-]")}),
           section("schmitt",
                   "The Schmitt trigger on the foot force sensor (detector schmitt). A force set "
                   "to auto is the kit's Go2 design (25 / 10 N, 150 N full scale, -10 N) scaled "
                   "to the robot's standing foot load, m g / n_feet",
                   {numberOrAuto(
                        "f_high", [](S& s) -> std::optional<double>& { return s.schmitt.f_high; },
                        0, 1e5, "touchdown threshold [N]"),
                    numberOrAuto(
                        "f_low", [](S& s) -> std::optional<double>& { return s.schmitt.f_low; }, 0,
                        1e5, "lift-off threshold, at most f_high [N]"),
                    number(
                        "t_on", [](S& s) -> double& { return s.schmitt.t_on; }, 0, 1,
                        "how long f_high must hold [s]"),
                    number(
                        "t_off", [](S& s) -> double& { return s.schmitt.t_off; }, 0, 1,
                        "how long f_low must hold [s]"),
                    numberOrAuto(
                        "saturation",
                        [](S& s) -> std::optional<double>& { return s.schmitt.saturation; }, 1, 1e6,
                        "the sensor's full scale [N]"),
                    number(
                        "stuck_time", [](S& s) -> double& { return s.schmitt.stuck_time; }, 0, 100,
                        "saturated this long: a stuck sensor [s]"),
                    numberOrAuto(
                        "negative_limit",
                        [](S& s) -> std::optional<double>& { return s.schmitt.negative_limit; },
                        -1e5, 0, "a reading below this is a faulty sensor [N]")},
                   [](const Settings& s, const io::YamlValue& v) {
                     const SchmittSettings& t = s.schmitt;
                     if (t.f_low.has_value() != t.f_high.has_value()) {
                       v.fail("give f_high and f_low together (or neither: auto)");
                     }
                     if (t.f_low && *t.f_low > *t.f_high) v.fail("f_low must not exceed f_high");
                     if (t.saturation && t.f_high && !(*t.saturation > *t.f_high)) {
                       v.fail("saturation must be above f_high");
                     }
                   }),
           section("gait",
                   "The robot's planned gait on a recorded log (detector gait-clock; the clock of "
                   "probabilistic and fallback): foot k stands while frac((t - start) / period - "
                   "offsets[k]) < duty",
                   {number(
                        "period", [](S& s) -> double& { return s.gait.period; }, 0, 100,
                        "gait period, 0: the robot has no planned gait [s]"),
                    number(
                        "duty", [](S& s) -> double& { return s.gait.duty; }, 0.01, 1,
                        "planned stance fraction of the period, 1: never lifts [-]"),
                    numbers(
                        "offsets", [](S& s) -> std::vector<double>& { return s.gait.offsets; }, 0,
                        1, "phase offset of each foot in foot-id order, one per foot [periods]"),
                    number(
                        "start", [](S& s) -> double& { return s.gait.start; }, -1e6, 1e6,
                        "when the clock starts; every foot stands before [s]")},
                   [](const Settings& s, const io::YamlValue& v) {
                     if (s.gait.period > 0.0 && s.gait.offsets.empty()) {
                       v.fail("a gait (period > 0) needs its offsets, one per foot");
                     }
                     if (s.gait.offsets.size() > static_cast<std::size_t>(io::kMaxFeet)) {
                       v.find("offsets")->fail("at most " + std::to_string(io::kMaxFeet) +
                                               " feet, got " +
                                               std::to_string(s.gait.offsets.size()));
                     }
                   })},
          [](const Settings& s, const io::YamlValue& v) {
            const std::vector<std::string> allowed = contactSources();
            if (std::find(allowed.begin(), allowed.end(), s.pipeline.contact) == allowed.end()) {
              v.find("detector")->oneOf(allowed);
            }
          }),
      section(
          "gating", "Innovation gating (section 57.9)",
          {flag(
               "enabled", [](S& s) -> bool& { return s.gating.enabled; },
               "reject a foot measurement whose innovation fails the chi-square gate"),
           number(
               "n_sigma", [](S& s) -> double& { return s.gating.n_sigma; }, 0.5, 10,
               "the gate: n sigma, as a probability per degree of freedom [-]"),
           number(
               "max_gated_time", [](S& s) -> double& { return s.gating.max_gated_time; }, 0, 100,
               "a foot gated at every step this long is re-initialised from its measurement, "
               "0: at once [s]")}),
      section(
          "initialisation", "Stationary initialisation (section 57.9)",
          {flag(
               "enabled", [](S& s) -> bool& { return s.initialisation.enabled; },
               "find a still window first: tilt from gravity, gyro bias from the mean rate"),
           number(
               "duration", [](S& s) -> double& { return s.initialisation.duration; }, 0.01, 60,
               "length of the still window averaged [s]"),
           number(
               "gyro_std_max", [](S& s) -> double& { return s.initialisation.gyro_std_max; }, 0, 1,
               "above this per axis the robot is moving [rad/s]"),
           number(
               "accel_std_max", [](S& s) -> double& { return s.initialisation.accel_std_max; }, 0,
               10, "above this per axis the robot is moving [m/s^2]"),
           number(
               "max_wait", [](S& s) -> double& { return s.initialisation.max_wait; }, 0, 3600,
               "without a still window by then: give up, start as the log does [s]"),
           choice<GyroBiasStart>(
               "gyro_bias", [](S& s) -> GyroBiasStart& { return s.gyro_bias_start; },
               {{GyroBiasStart::kZero, "zero"}, {GyroBiasStart::kStillWindow, "still-window"}},
               "where legkit run and eval start every estimator's gyro bias: zero, or the "
               "mean rate of the still window at the log's start (a real IMU's turn-on bias)")}),
      section(
          "monitors", "Sensor-health and covariance monitors (section 57.9)",
          {number(
               "imu_dropout_periods",
               [](S& s) -> double& { return s.monitors.imu_dropout_periods; }, 1.01, 1000,
               "a gap over this many nominal periods is an IMU dropout [-]"),
           number(
               "stuck_encoder_time", [](S& s) -> double& { return s.monitors.stuck_encoder_time; },
               1e-3, 100, "a joint frozen this long while the body moves is a stuck encoder [s]"),
           number(
               "stuck_encoder_gyro", [](S& s) -> double& { return s.monitors.stuck_encoder_gyro; },
               1e-3, 100, "the body moves: |gyro| beyond this ... [rad/s]"),
           number(
               "stuck_encoder_speed",
               [](S& s) -> double& { return s.monitors.stuck_encoder_speed; }, 1e-3, 100,
               "... or the estimated speed beyond this [m/s]"),
           number(
               "force_drift_window", [](S& s) -> double& { return s.monitors.force_drift_window; },
               1e-3, 600, "time constant of the mean (sensor - model) foot force [s]"),
           number(
               "force_drift_sigma", [](S& s) -> double& { return s.monitors.force_drift_sigma; },
               0.5, 100, "a mean beyond this many force_sigma is a drifting sensor [-]"),
           number(
               "force_sigma", [](S& s) -> double& { return s.monitors.force_sigma; }, 1e-3, 1e4,
               "sigma of (sensor - model) normal force per sample on a healthy robot [N]"),
           number(
               "exteroception_timeout",
               [](S& s) -> double& { return s.monitors.exteroception_timeout; }, 1e-3, 1e5,
               "without an exteroceptive update this long: alarm [s]"),
           number(
               "position_sigma_max", [](S& s) -> double& { return s.monitors.position_sigma_max; },
               1e-3, 1e6, "covariance-growth alarm on the position [m]"),
           number(
               "velocity_sigma_max", [](S& s) -> double& { return s.monitors.velocity_sigma_max; },
               1e-3, 1e3, "covariance-growth alarm on the velocity [m/s]")}),
  };
  return root;
}

std::vector<std::string> keysOf(const std::vector<Node>& nodes) {
  std::vector<std::string> keys;
  for (const Node& n : nodes) keys.push_back(n.key);
  return keys;
}

// Reads the keys of `nodes` present in the map `v`; a null value (an empty section) keeps them.
void readNodes(const std::vector<Node>& nodes, const io::YamlValue& v, Settings& s) {
  if (v.isNull()) return;
  v.checkKeys(keysOf(nodes));
  for (const Node& n : nodes) {
    const std::optional<io::YamlValue> value = n.key.empty() ? std::nullopt : v.find(n.key);
    if (!value) continue;
    if (n.children.empty()) {
      n.read(s, *value);
    } else {
      readNodes(n.children, *value, s);
      if (n.check) n.check(s, *value);
    }
  }
}

void writeNodes(const std::vector<Node>& nodes, const Settings& s, int indent, std::ostream& out) {
  const std::string pad(indent, ' ');
  for (const Node& n : nodes) {
    if (!n.children.empty()) {
      out << (indent == 0 ? "\n" : "") << pad << "# " << n.comment << "\n" << pad << n.key << ":\n";
      writeNodes(n.children, s, indent + 2, out);
    } else if (n.write) {
      out << (indent == 0 ? "\n" : "") << pad << "# " << n.comment << "\n"
          << pad << n.key << ": " << n.write(s) << "\n";
    }
  }
}

Settings readSettings(const io::YamlValue& root, Settings s = defaultSettings()) {
  if (!root.isNull() && !root.isMap()) root.fail("expected a map of sections at the top level");
  readNodes(schema(), root, s);
  return s;
}

}  // namespace

FrontendNoise frontendNoise(const Settings& settings) {
  FrontendNoise noise = settings.frontend;
  noise.foot_rotations = settings.feet.flat;
  return noise;
}

Settings defaultSettings() {
  Settings s;
  s.pipeline.contact = "fallback";
  s.pipeline.slip = slip::SlipReaction::kInflate;
  s.pipeline.settle_time = kRecommendedSettleTime;
  s.feet.stance_density = kRobotStanceDensity;
  s.linear_kf.foot_velocity_sigma = kRobotFootVelocitySigma;
  return s;
}

Settings withExactLegs(Settings s) {
  s.feet = FootSettings{};
  s.linear_kf.foot_velocity_sigma = LinearKfSettings{}.foot_velocity_sigma;
  return s;
}

Settings loadSettings(const std::string& path) {
  Settings s = readSettings(io::YamlValue::parseFile(path));
  s.source = path;
  // A relative robot model is next to the settings file, wherever the program runs.
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (!s.robot.model.empty() && std::filesystem::path(s.robot.model).is_relative() &&
      !dir.empty()) {
    s.robot.model = (dir / s.robot.model).string();
  }
  return s;
}

Settings settingsFromYaml(const std::string& text, const std::string& name, const Settings& base) {
  Settings s = readSettings(io::YamlValue::parse(text, name), base);
  s.source = name;
  return s;
}

std::string settingsYaml(const Settings& settings) {
  std::ostringstream out;
  out << "# legkit settings (`legkit config --print` writes this file; `legkit run --config FILE`\n"
         "# reads one). Every key is optional: a key left out keeps the value shown here.\n";
  writeNodes(schema(), settings, 0, out);
  return out.str();
}

std::optional<contact::GaitSchedule> gaitSchedule(const Settings& settings, int num_feet) {
  const GaitSettings& g = settings.gait;
  if (!(g.period > 0.0)) return std::nullopt;
  if (g.offsets.size() != static_cast<std::size_t>(num_feet)) {
    throw std::invalid_argument((settings.source.empty() ? std::string() : settings.source + ": ") +
                                "contact.gait.offsets: " + std::to_string(g.offsets.size()) +
                                " offsets for a robot of " + std::to_string(num_feet) +
                                " feet (one per foot, in foot-id order)");
  }
  contact::GaitSchedule schedule;
  schedule.period = g.period;
  schedule.duty = g.duty;
  schedule.offset.fill(0.0);
  std::copy(g.offsets.begin(), g.offsets.end(), schedule.offset.begin());
  schedule.start = g.start;
  schedule.num_feet = num_feet;
  return schedule;
}

double robotMass(const Settings& settings, const model::LegKinematics* legs) {
  if (settings.robot.mass > 0.0) return settings.robot.mass;
  return legs ? legs->mass() : model::QuadrupedInertia::go2().totalMass();
}

contact::DetectorContext detectorContext(const Settings& settings, double mass, int num_feet) {
  contact::DetectorContext c;
  contact::scaleForcesToRobot(c, mass, num_feet);
  const SchmittSettings& t = settings.schmitt;
  if (t.f_high) c.schmitt.f_high = *t.f_high;
  if (t.f_low) c.schmitt.f_low = *t.f_low;
  if (t.saturation) c.schmitt.saturation = *t.saturation;
  if (t.negative_limit) c.schmitt.negative_limit = *t.negative_limit;
  c.schmitt.t_on = t.t_on;
  c.schmitt.t_off = t.t_off;
  c.schmitt.stuck_time = t.stuck_time;
  return c;
}

}  // namespace legkit
