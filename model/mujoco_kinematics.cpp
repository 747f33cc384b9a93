#include "model/mujoco_kinematics.hpp"

#include "model/quadruped_leg_kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace legkit::model {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error("robot model '" + path + "': " + what);
}

// The names of MuJoCo objects of one type, for an error message: "a, b, c" ("none" if empty).
std::string knownNames(const mjModel& m, mjtObj type, int count) {
  std::string list;
  for (int i = 0; i < count; ++i) {
    const char* name = mj_id2name(&m, type, i);
    if (name == nullptr || name[0] == '\0') continue;
    list += (list.empty() ? "" : ", ") + std::string(name);
  }
  return list.empty() ? "none" : list;
}

// The id of the object called `name`, -1 when there is none (or the name is empty: MuJoCo would
// match an unnamed object).
int findId(const mjModel& m, mjtObj type, const std::string& name) {
  return name.empty() ? -1 : mj_name2id(&m, type, name.c_str());
}

// True when body `b` lies strictly below body `ancestor` in the kinematic tree.
bool below(const mjModel& m, int b, int ancestor) {
  if (b == ancestor) return false;
  while (b != 0 && b != ancestor) b = m.body_parentid[b];
  return b == ancestor;
}

// The name of a MuJoCo object, "#<id>" when it has none.
std::string objectName(const mjModel& m, mjtObj type, int id) {
  const char* name = mj_id2name(&m, type, id);
  return name != nullptr && name[0] != '\0' ? name : "#" + std::to_string(id);
}

// --- Just enough XML to find the elements MuJoCo's URDF compiler settings go into. -----------

struct StartTag {
  std::size_t begin = std::string::npos;  // position of '<'
  std::size_t name_end = 0;               // just after the element name
  std::size_t end = 0;                    // just after '>'
  std::string name;
  bool self_closing = false;
};

// The next start tag at or after `from`, skipping comments, processing instructions, CDATA,
// declarations and end tags; begin == npos when there is none (or the markup is cut off).
StartTag nextStartTag(const std::string& s, std::size_t from) {
  StartTag tag;
  for (std::size_t i = s.find('<', from); i != std::string::npos; i = s.find('<', i)) {
    const auto skipPast = [&](const char* close) {
      const std::size_t at = s.find(close, i);
      return at == std::string::npos ? at : at + std::strlen(close);
    };
    if (s.compare(i, 4, "<!--") == 0) {
      i = skipPast("-->");
    } else if (s.compare(i, 9, "<![CDATA[") == 0) {
      i = skipPast("]]>");
    } else if (s.compare(i, 2, "<?") == 0) {
      i = skipPast("?>");
    } else if (s.compare(i, 2, "<!") == 0 || s.compare(i, 2, "</") == 0) {
      i = skipPast(">");
    } else {
      std::size_t j = i + 1;
      while (j < s.size() && std::strchr(" \t\r\n/>", s[j]) == nullptr) ++j;
      char quote = 0;  // a '>' inside an attribute value does not end the tag
      std::size_t k = j;
      for (; k < s.size(); ++k) {
        if (quote != 0) {
          if (s[k] == quote) quote = 0;
        } else if (s[k] == '"' || s[k] == '\'') {
          quote = s[k];
        } else if (s[k] == '>') {
          break;
        }
      }
      if (k >= s.size()) return tag;
      tag.begin = i;
      tag.name_end = j;
      tag.end = k + 1;
      tag.name = s.substr(i + 1, j - i - 1);
      tag.self_closing = s[k - 1] == '/';
      return tag;
    }
    if (i == std::string::npos) return tag;
  }
  return tag;
}

// Just after the end tag </name> of the element that `tag` opens (URDF does not nest a <visual>
// or <collision> in one of its own name); npos when it is not closed.
std::size_t elementEnd(const std::string& s, const StartTag& tag) {
  if (tag.self_closing) return tag.end;
  const std::string close = "</" + tag.name;
  for (std::size_t at = s.find(close, tag.end); at != std::string::npos;
       at = s.find(close, at + 1)) {
    const std::size_t after = at + close.size();
    if (after < s.size() && std::strchr(" \t\r\n>", s[after]) != nullptr) {
      const std::size_t end = s.find('>', after);
      return end == std::string::npos ? end : end + 1;
    }
  }
  return std::string::npos;
}

// Removes every <visual> and <collision> element, keeping its line breaks (so MuJoCo's line
// numbers stay the file's). The kit reads kinematics only: these elements carry nothing it uses,
// and their meshes are the files a URDF taken out of its ROS package no longer has (MuJoCo
// refuses a missing mesh). Masses come from <inertial>, which stays. An element left unclosed
// stays, for MuJoCo to report.
void stripGeometry(std::string& xml) {
  std::size_t from = 0;
  for (StartTag t = nextStartTag(xml, from); t.begin != std::string::npos;
       t = nextStartTag(xml, from)) {
    from = t.end;
    if (t.name != "visual" && t.name != "collision") continue;
    const std::size_t end = elementEnd(xml, t);
    if (end == std::string::npos) return;
    const auto first = xml.begin() + static_cast<std::ptrdiff_t>(t.begin);
    const auto lines = std::count(first, first + static_cast<std::ptrdiff_t>(end - t.begin), '\n');
    xml.replace(t.begin, end - t.begin, static_cast<std::size_t>(lines), '\n');
    from = t.begin;
  }
}

// The URDF text with its geometry stripped (stripGeometry) and the compiler settings of the
// header's comment added (no line added, so MuJoCo's line numbers stay the file's); any other
// document unchanged. Returns whether it is a URDF (root element <robot>).
bool prepareUrdf(std::string& xml) {
  const StartTag root = nextStartTag(xml, 0);
  if (root.begin == std::string::npos || root.name != "robot" || root.self_closing) return false;
  stripGeometry(xml);
  StartTag compiler, mujoco;
  for (StartTag t = nextStartTag(xml, root.end); t.begin != std::string::npos;
       t = nextStartTag(xml, t.end)) {
    if (t.name == "compiler" && compiler.begin == std::string::npos) compiler = t;
    if (t.name == "mujoco" && mujoco.begin == std::string::npos) mujoco = t;
  }
  static constexpr const char* kSettings[][2] = {
      {"fusestatic", "false"}, {"boundmass", "1e-6"}, {"boundinertia", "1e-10"}};
  if (compiler.begin != std::string::npos) {
    const std::string attributes = xml.substr(compiler.name_end, compiler.end - compiler.name_end);
    std::string added;
    for (const auto& kv : kSettings) {
      if (attributes.find(kv[0]) == std::string::npos) {
        added += std::string(" ") + kv[0] + "=\"" + kv[1] + "\"";
      }
    }
    xml.insert(compiler.name_end, added);
    return true;
  }
  std::string element = "<compiler";
  for (const auto& kv : kSettings) element += std::string(" ") + kv[0] + "=\"" + kv[1] + "\"";
  element += "/>";
  if (mujoco.begin == std::string::npos) {
    xml.insert(root.end, "<mujoco>" + element + "</mujoco>");
  } else if (mujoco.self_closing) {
    xml.replace(mujoco.end - 2, 2, ">" + element + "</mujoco>");
  } else {
    xml.insert(mujoco.end, element);
  }
  return true;
}

// The attributes of a start tag, in order, as (name, value).
std::vector<std::pair<std::string, std::string>> attributes(const std::string& s,
                                                            const StartTag& tag) {
  std::vector<std::pair<std::string, std::string>> out;
  std::size_t i = tag.name_end;
  while (true) {
    const std::size_t name = s.find_first_not_of(" \t\r\n", i);
    if (name == std::string::npos || name >= tag.end || s[name] == '/' || s[name] == '>') break;
    const std::size_t eq = s.find('=', name);
    const std::size_t open = s.find_first_of("\"'", eq);
    if (eq == std::string::npos || open == std::string::npos || open >= tag.end) break;
    const std::size_t close = s.find(s[open], open + 1);
    if (close == std::string::npos || close >= tag.end) break;
    std::string key = s.substr(name, eq - name);
    key.erase(key.find_last_not_of(" \t\r\n") + 1);
    out.emplace_back(key, s.substr(open + 1, close - open - 1));
    i = close + 1;
  }
  return out;
}

// True when `value` is one or more whitespace-separated finite numbers.
bool finiteNumbers(const std::string& value) {
  std::istringstream tokens(value);
  int count = 0;
  for (std::string token; tokens >> token; ++count) {
    char* end = nullptr;
    const double x = std::strtod(token.c_str(), &end);
    if (end != token.c_str() + token.size() || !std::isfinite(x)) return false;
  }
  return count > 0;
}

// Throws naming the line when a URDF declares entities (<!ENTITY> in its DOCTYPE) or holds an
// include (<xi:include>, <xacro:include>) or any other xacro element: MuJoCo's XML reader expands
// no entity and skips elements it does not know, so an entity would stay "&name;" and the included
// links and joints would be missing without a word (and nothing outside the file is ever read).
void checkUrdfPlain(const std::string& path, const std::string& xml) {
  const StartTag root = nextStartTag(xml, 0);
  if (const std::size_t entity = xml.find("<!ENTITY"); entity < root.begin) {
    const auto line = 1 + std::count(xml.begin(), xml.begin() + entity, '\n');
    fail(path, "line " + std::to_string(line) +
                   ": <!ENTITY>: the kit reads a plain URDF, and expands no entity");
  }
  for (StartTag t = root; t.begin != std::string::npos; t = nextStartTag(xml, t.end)) {
    const bool include =
        t.name.size() >= 8 && t.name.compare(t.name.size() - 8, 8, ":include") == 0;
    if (include || t.name.rfind("xacro:", 0) == 0) {
      const auto line = 1 + std::count(xml.begin(), xml.begin() + t.begin, '\n');
      fail(path, "line " + std::to_string(line) + ": <" + t.name +
                     ">: the kit reads a plain URDF, without includes or xacro (expand it "
                     "first: xacro model.urdf.xacro > model.urdf)");
    }
  }
}

// Throws naming the line and the joint or link when a numeric attribute of a URDF's kinematics
// or inertia is not finite numbers: MuJoCo reads "nan" or a word as 0 and loads the robot.
void checkUrdfNumbers(const std::string& path, const std::string& xml) {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> kNumeric = {
      {"origin", {"xyz", "rpy"}},
      {"axis", {"xyz"}},
      {"limit", {"lower", "upper", "effort", "velocity"}},
      {"mass", {"value"}},
      {"inertia", {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"}},
      {"dynamics", {"damping", "friction"}}};
  std::string owner = "the robot";  // the joint or link being read
  for (StartTag t = nextStartTag(xml, 0); t.begin != std::string::npos;
       t = nextStartTag(xml, t.end)) {
    if (t.name == "joint" || t.name == "link") {
      for (const auto& [key, value] : attributes(xml, t)) {
        if (key == "name") owner = t.name + " '" + value + "'";
      }
      continue;
    }
    const auto element = std::find_if(kNumeric.begin(), kNumeric.end(),
                                      [&](const auto& e) { return e.first == t.name; });
    if (element == kNumeric.end()) continue;
    for (const auto& [key, value] : attributes(xml, t)) {
      const std::vector<std::string>& numeric = element->second;
      if (std::find(numeric.begin(), numeric.end(), key) == numeric.end() || finiteNumbers(value)) {
        continue;
      }
      const auto line =
          1 + std::count(xml.begin(), xml.begin() + static_cast<std::ptrdiff_t>(t.begin), '\n');
      fail(path, "line " + std::to_string(line) + ", " + owner + ": <" + t.name + " " + key +
                     "=\"" + value + "\">: expected finite numbers");
    }
  }
}

// Throws naming the first body, joint or site whose pose, axis, range, mass or inertia is not
// finite: MuJoCo loads an MJCF "nan" with a warning only.
void checkFinite(const std::string& path, const mjModel& m) {
  const auto finite = [](const mjtNum* x, int n) {
    return std::all_of(x, x + n, [](mjtNum v) { return std::isfinite(v); });
  };
  const auto refuse = [&](mjtObj type, const char* what, int id) {
    fail(path, std::string(what) + " '" + objectName(m, type, id) +
                   "': a number that is not finite (NaN or inf in the file)");
  };
  for (int b = 0; b < m.nbody; ++b) {
    if (!finite(m.body_pos + 3 * b, 3) || !finite(m.body_quat + 4 * b, 4) ||
        !finite(m.body_ipos + 3 * b, 3) || !finite(m.body_iquat + 4 * b, 4) ||
        !finite(m.body_mass + b, 1) || !finite(m.body_inertia + 3 * b, 3)) {
      refuse(mjOBJ_BODY, "body", b);
    }
  }
  for (int j = 0; j < m.njnt; ++j) {
    if (!finite(m.jnt_pos + 3 * j, 3) || !finite(m.jnt_axis + 3 * j, 3) ||
        !finite(m.jnt_range + 2 * j, 2)) {
      refuse(mjOBJ_JOINT, "joint", j);
    }
  }
  for (int s = 0; s < m.nsite; ++s) {
    if (!finite(m.site_pos + 3 * s, 3) || !finite(m.site_quat + 4 * s, 4)) {
      refuse(mjOBJ_SITE, "site", s);
    }
  }
}

// MuJoCo's warnings on this thread go into a string while a collector lives, else to stderr
// (never to MuJoCo's default stdout and MUJOCO_LOG.TXT in the working directory).
thread_local std::string* t_warnings = nullptr;

void collectWarning(const char* message) {
  if (t_warnings != nullptr) {
    *t_warnings += (t_warnings->empty() ? "" : "; ") + std::string(message);
  } else {
    std::fprintf(stderr, "MuJoCo warning: %s\n", message);
  }
}

struct WarningCollector {
  explicit WarningCollector(std::string& into) {
    mju_user_warning = collectWarning;
    t_warnings = &into;
  }
  ~WarningCollector() { t_warnings = nullptr; }
  WarningCollector(const WarningCollector&) = delete;
  WarningCollector& operator=(const WarningCollector&) = delete;
};

struct VfsDeleter {
  void operator()(mjVFS* vfs) const {
    mj_deleteVFS(vfs);
    delete vfs;
  }
};

// MuJoCo's model of `path`. A URDF goes through a virtual file under the same path, so that
// MuJoCo still finds its meshes relative to the file's directory.
MjModelPtr load(const std::string& path) {
  // Regular files only, and at most 16 MiB of them: a directory fails on its first read without
  // the path, a FIFO blocks in open(), /dev/zero never ends (the same checks as io/input_file.hpp,
  // which this layer cannot include).
  namespace fs = std::filesystem;
  std::error_code ignored;
  const fs::file_status status = fs::status(path, ignored);
  if (fs::is_directory(status)) fail(path, "is a directory, not a file");
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    fail(path, "is not a regular file (a device, a FIFO or a socket)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file (no such file, or not readable)");
  constexpr std::size_t kMaxBytes = std::size_t{16} << 20;
  std::string xml;
  char buffer[1 << 16];
  while (in) {
    in.read(buffer, sizeof buffer);
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n > kMaxBytes - xml.size()) {
      fail(path, "is larger than the 16 MiB (" + std::to_string(kMaxBytes) +
                     " bytes) a robot model may be; nothing beyond that is read");
    }
    xml.append(buffer, n);
  }
  if (in.bad()) fail(path, "read error");
  const std::size_t first = xml.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) fail(path, "is empty: a robot model is a URDF or MJCF file");
  if (xml[first] != '<') {
    fail(path, "is not XML (a URDF or MJCF file begins with '<'; this one with byte " +
                   std::to_string(static_cast<unsigned char>(xml[first])) + ")");
  }
  char error[1000] = "";
  MjModelPtr m;
  std::string warnings;
  const WarningCollector collector(warnings);
  if (prepareUrdf(xml)) {
    checkUrdfPlain(path, xml);
    checkUrdfNumbers(path, xml);
    const std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
    mj_defaultVFS(vfs.get());
    if (mj_makeEmptyFileVFS(vfs.get(), path.c_str(), static_cast<int>(xml.size())) != 0) {
      fail(path, "MuJoCo's virtual file system refused the file");
    }
    const int file = mj_findFileVFS(vfs.get(), path.c_str());
    if (file < 0) fail(path, "MuJoCo's virtual file system lost the file");
    std::memcpy(vfs->filedata[file], xml.data(), xml.size());
    m.reset(mj_loadXML(path.c_str(), vfs.get(), error, sizeof(error)));
  } else {
    m.reset(mj_loadXML(path.c_str(), nullptr, error, sizeof(error)));
  }
  if (!m) {
    std::string message = error;
    while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) {
      message.pop_back();
    }
    fail(path, "MuJoCo cannot load it: " + message);
  }
  // MuJoCo loads an MJCF "nan" with a warning only (and as a finite number).
  if (!warnings.empty()) fail(path, "MuJoCo warns: " + warnings);
  checkFinite(path, *m);
  return m;
}

}  // namespace

MujocoLegKinematics MujocoLegKinematics::fromFile(const std::string& path, const std::string& base,
                                                  const std::vector<std::string>& feet,
                                                  const std::vector<std::string>& joints) {
  if (feet.empty()) fail(path, "no foot named (name one site or body per foot)");
  if (feet.size() > static_cast<std::size_t>(kMaxLegFeet)) {
    fail(path, std::to_string(feet.size()) + " feet named, the kit handles at most " +
                   std::to_string(kMaxLegFeet));
  }
  if (joints.size() > static_cast<std::size_t>(kMaxLegJoints)) {
    fail(path, std::to_string(joints.size()) + " joints named, the kit handles at most " +
                   std::to_string(kMaxLegJoints));
  }
  MujocoLegKinematics robot;
  robot.path_ = path;
  robot.model_ = load(path);
  const mjModel& m = *robot.model_;

  robot.base_ = findId(m, mjOBJ_BODY, base);
  if (robot.base_ < 0) {
    fail(path, "no body named '" + base +
                   "' for the base (its bodies: " + knownNames(m, mjOBJ_BODY, m.nbody) + ")");
  }

  for (const std::string& name : feet) {
    for (const Frame& f : robot.feet_) {
      if (f.name == name) fail(path, "foot '" + name + "' named twice");
    }
    Frame f;
    f.name = name;
    f.id = findId(m, mjOBJ_SITE, name);
    f.is_site = f.id >= 0;
    if (f.is_site) {
      f.body = m.site_bodyid[f.id];
    } else {
      f.id = f.body = findId(m, mjOBJ_BODY, name);
    }
    if (f.id < 0) {
      fail(path, "no site or body named '" + name +
                     "' for a foot (its sites: " + knownNames(m, mjOBJ_SITE, m.nsite) +
                     "; its bodies: " + knownNames(m, mjOBJ_BODY, m.nbody) + ")");
    }
    if (!below(m, f.body, robot.base_)) {
      fail(path, "foot '" + name + "' (on body '" + objectName(m, mjOBJ_BODY, f.body) +
                     "') is not below the base '" + base +
                     "' in the kinematic tree: no leg joint moves it relative to the base");
    }
    for (const Frame& other : robot.feet_) {  // each foot ends a leg of its own
      if (other.body == f.body || below(m, f.body, other.body) || below(m, other.body, f.body)) {
        fail(path, "feet '" + other.name + "' and '" + name + "' are on one leg (bodies '" +
                       objectName(m, mjOBJ_BODY, other.body) + "' and '" +
                       objectName(m, mjOBJ_BODY, f.body) +
                       "': one body, or one below the other in the kinematic tree)");
      }
    }
    robot.feet_.push_back(f);
  }

  const auto addJoint = [&](int j) {
    robot.joints_.push_back(
        Joint{objectName(m, mjOBJ_JOINT, j), m.jnt_qposadr[j], m.jnt_dofadr[j]});
  };
  const auto isLegJoint = [&](int j) {
    return (m.jnt_type[j] == mjJNT_HINGE || m.jnt_type[j] == mjJNT_SLIDE) &&
           below(m, m.jnt_bodyid[j], robot.base_);
  };
  if (joints.empty()) {
    for (int j = 0; j < m.njnt; ++j) {
      if (isLegJoint(j)) addJoint(j);
    }
    if (robot.joints_.size() > static_cast<std::size_t>(kMaxLegJoints)) {
      fail(path, std::to_string(robot.joints_.size()) + " hinge and slide joints below the base '" +
                     base + "', the kit handles at most " + std::to_string(kMaxLegJoints) +
                     " (name the leg joints)");
    }
  }
  for (const std::string& name : joints) {
    const int j = findId(m, mjOBJ_JOINT, name);
    if (j < 0) {
      fail(path, "no joint named '" + name +
                     "' (its joints: " + knownNames(m, mjOBJ_JOINT, m.njnt) + ")");
    }
    for (const Joint& known : robot.joints_) {
      if (known.name == name) fail(path, "joint '" + name + "' named twice");
    }
    if (!isLegJoint(j)) {
      fail(path, "joint '" + name + "' is not a hinge or slide joint below the base '" + base +
                     "' (a leg joint moves a foot relative to the base)");
    }
    addJoint(j);
  }
  if (robot.joints_.empty()) fail(path, "no hinge or slide joint below the base '" + base + "'");

  robot.data_ = makeData(m);
  for (int j = 0; j < m.njnt; ++j) {  // every free joint at the identity pose
    if (m.jnt_type[j] != mjJNT_FREE) continue;
    mjtNum* qpos = robot.data_->qpos + m.jnt_qposadr[j];
    for (int i = 0; i < 7; ++i) qpos[i] = i == 3 ? 1.0 : 0.0;  // (x, y, z, w, x, y, z)
  }
  robot.jacp_.assign(3 * static_cast<std::size_t>(m.nv), 0.0);
  return robot;
}

std::string MujocoLegKinematics::footName(int foot) const {
  return feet_.at(static_cast<std::size_t>(foot)).name;
}

std::string MujocoLegKinematics::jointName(int joint) const {
  return joints_.at(static_cast<std::size_t>(joint)).name;
}

double MujocoLegKinematics::mass() const {
  return mj_getTotalmass(model_.get());
}

void MujocoLegKinematics::update(const LegJointVector& q) const {
  const int n = numJoints();
  if (have_q_ && q.head(n) == q_last_.head(n)) return;
  if (!q.head(n).allFinite()) {
    throw std::invalid_argument("robot model '" + path_ + "': joint angles are not finite");
  }
  for (int k = 0; k < n; ++k) data_->qpos[joints_[k].qpos] = q[k];
  mj_kinematics(model_.get(), data_.get());
  mj_comPos(model_.get(), data_.get());  // cdof and subtree_com for mj_jac
  q_last_ = q;
  have_q_ = true;
}

const MujocoLegKinematics::Frame& MujocoLegKinematics::footFrame(int foot,
                                                                 const LegJointVector& q) const {
  if (foot < 0 || foot >= numFeet()) {
    throw std::out_of_range("robot model '" + path_ + "': foot id " + std::to_string(foot) +
                            " is out of range (it has " + std::to_string(numFeet()) + " feet)");
  }
  update(q);
  return feet_[foot];
}

namespace {
using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
}  // namespace

void MujocoLegKinematics::foot(int foot, const LegJointVector& q, Eigen::Vector3d& p_B,
                               FootJacobian& J) const {
  const Frame& f = footFrame(foot, q);
  const mjModel& m = *model_;
  const mjData& d = *data_;
  const mjtNum* x_f = f.is_site ? d.site_xpos + 3 * f.id : d.xpos + 3 * f.id;
  const Eigen::Map<const RowMajor3> R_WB(d.xmat + 9 * base_);  // base axes in the world
  const Eigen::Map<const Eigen::Vector3d> x_B(d.xpos + 3 * base_);
  p_B = R_WB.transpose() * (Eigen::Map<const Eigen::Vector3d>(x_f) - x_B);
  mj_jac(&m, &d, jacp_.data(), nullptr, x_f, f.body);  // J_f, world frame, 3 x nv
  const Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>> J_f(
      jacp_.data(), 3, m.nv);
  J.setZero();
  for (int k = 0; k < numJoints(); ++k) J.col(k) = R_WB.transpose() * J_f.col(joints_[k].dof);
}

bool MujocoLegKinematics::footRotation(int foot, const LegJointVector& q, Eigen::Matrix3d& R_BF,
                                       FootJacobian& J_w) const {
  const Frame& f = footFrame(foot, q);
  const mjModel& m = *model_;
  const mjData& d = *data_;
  const Eigen::Map<const RowMajor3> R_WB(d.xmat + 9 * base_);
  const Eigen::Map<const RowMajor3> R_WF(f.is_site ? d.site_xmat + 9 * f.id : d.xmat + 9 * f.id);
  R_BF = R_WB.transpose() * R_WF;
  // The rotational Jacobian is the same for every point of the body: the body's origin will do.
  mj_jac(&m, &d, nullptr, jacp_.data(), d.xpos + 3 * f.body, f.body);  // J_w,F, world, 3 x nv
  const Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>> J_f(
      jacp_.data(), 3, m.nv);
  J_w.setZero();
  for (int k = 0; k < numJoints(); ++k) J_w.col(k) = R_WB.transpose() * J_f.col(joints_[k].dof);
  return true;
}

std::unique_ptr<LegKinematics> makeLegKinematics(const std::string& model, const std::string& base,
                                                 const std::vector<std::string>& feet,
                                                 const std::vector<std::string>& joints) {
  if (!model.empty()) {
    return std::make_unique<MujocoLegKinematics>(
        MujocoLegKinematics::fromFile(model, base, feet, joints));
  }
  if (!base.empty() || !feet.empty() || !joints.empty()) {
    throw std::runtime_error(
        "robot: a base, feet or joints are named but no model file (the built-in Go2 has its own)");
  }
  return std::make_unique<QuadrupedLegKinematics>();
}

}  // namespace legkit::model
