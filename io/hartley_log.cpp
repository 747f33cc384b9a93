#include "io/hartley_log.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "io/input_file.hpp"
#include "io/log_error.hpp"

namespace legkit::io {

namespace {

constexpr int kFootFields = 44;  // id, quaternion (4), position (3), covariance (36)

// One line split into fields, with checked conversions that name the field in the error.
class Record {
 public:
  Record(const std::string& file, int line, const std::string& text) : file_(file), line_(line) {
    std::istringstream in(text);
    for (std::string token; in >> token;) fields_.push_back(token);
  }

  std::size_t size() const { return fields_.size(); }
  const std::string& kind() const { return fields_.front(); }

  double number(std::size_t i, const std::string& what) const {
    const std::string& token = fields_[i];
    errno = 0;
    char* end = nullptr;
    const double x = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || errno == ERANGE) {
      fail(what, "expected a number, got '" + token + "'");
    }
    if (!std::isfinite(x)) fail(what, "is not finite ('" + token + "')");
    return x;
  }

  int footId(std::size_t i, const std::string& what) const {
    const double x = number(i, what);
    if (x != std::round(x) || x < 0 || x >= kHartleyMaxFeet) {
      std::ostringstream os;
      os << "foot id must be an integer in [0, " << kHartleyMaxFeet << "), got " << fields_[i];
      fail(what, os.str());
    }
    return static_cast<int>(x);
  }

  [[noreturn]] void fail(const std::string& what, const std::string& message) const {
    throw LogError(file_, line_, what, message);
  }

 private:
  const std::string& file_;
  int line_;
  std::vector<std::string> fields_;
};

void readImu(const Record& r, HartleySample& s) {
  if (r.size() != 8) {
    r.fail("",
           "IMU record needs 8 fields (IMU t wx wy wz ax ay az), got " + std::to_string(r.size()));
  }
  static const char* names[] = {"wx", "wy", "wz", "ax", "ay", "az"};
  for (int i = 0; i < 3; ++i) s.imu.w_m(i) = r.number(2 + i, names[i]);
  for (int i = 0; i < 3; ++i) s.imu.a_m(i) = r.number(5 + i, names[3 + i]);
}

// CONTACT t id c ...: indicator[id] = c (0 or 1); -1 for the feet not listed.
void readContact(const Record& r, std::array<int, kHartleyMaxFeet>& indicator) {
  if (r.size() < 2 || (r.size() - 2) % 2 != 0) {
    r.fail("", "CONTACT record needs pairs 'id c' after the time, got " +
                   std::to_string(r.size() - 2) + " fields");
  }
  indicator.fill(-1);
  for (std::size_t i = 2; i < r.size(); i += 2) {
    const std::string n = std::to_string((i - 2) / 2);
    const int id = r.footId(i, "id" + n);
    if (indicator[id] != -1) r.fail("id" + n, "foot " + std::to_string(id) + " listed twice");
    const double c = r.number(i + 1, "c" + n);
    if (c != 0.0 && c != 1.0) r.fail("c" + n, "contact indicator must be 0 or 1");
    indicator[id] = static_cast<int>(c);
  }
}

void readKinematic(const Record& r, HartleySample& s) {
  if (r.size() < 2 || (r.size() - 2) % kFootFields != 0) {
    r.fail("", "KINEMATIC record needs 44 fields per foot after the time, got " +
                   std::to_string(r.size() - 2) + " fields");
  }
  s.num_feet = static_cast<int>((r.size() - 2) / kFootFields);
  if (s.num_feet > kHartleyMaxFeet) r.fail("", "more than 4 feet");
  for (int f = 0; f < s.num_feet; ++f) {
    const std::size_t at = 2 + static_cast<std::size_t>(f) * kFootFields;
    const std::string n = std::to_string(f);
    ContactMeasurement& c = s.feet[f];
    c.foot = r.footId(at, "id" + n);
    for (int g = 0; g < f; ++g) {
      if (s.feet[g].foot == c.foot) r.fail("id" + n, "foot listed twice");
    }
    for (int i = 0; i < 4; ++i) r.number(at + 1 + i, "q" + n);  // orientation: checked, unused
    for (int i = 0; i < 3; ++i) c.p_body(i) = r.number(at + 5 + i, "p" + n);
    Eigen::Matrix<double, 6, 6> C;
    for (int i = 0; i < 36; ++i) C(i / 6, i % 6) = r.number(at + 8 + i, "cov" + n);
    c.cov = C.bottomRightCorner<3, 3>();  // the position block
    c.v_body.reset();
  }
}

}  // namespace

int stanceFeet(const HartleySample& sample, std::array<ContactMeasurement, kHartleyMaxFeet>& out) {
  int n = 0;
  for (int f = 0; f < sample.num_feet; ++f) {
    if (sample.contact[f]) out[n++] = sample.feet[f];
  }
  return n;
}

HartleyLog parseHartleyLog(std::istream& in, const std::string& name) {
  HartleyLog log;
  log.file = name;
  std::string text;
  int line = 0;
  // Which records of the current timestamp have been seen: IMU first, then CONTACT, KINEMATIC.
  bool have_contact = true, have_kinematic = true;
  std::array<int, kHartleyMaxFeet> indicator{};
  const auto finish = [&](int at) {
    if (log.samples.empty()) return;
    HartleySample& s = log.samples.back();
    if (!have_contact || !have_kinematic) {
      throw LogError(name, at, "",
                     std::string("the sample of line ") + std::to_string(s.line) + " has no " +
                         (have_contact ? "KINEMATIC" : "CONTACT") + " record");
    }
    for (int f = 0; f < s.num_feet; ++f) {
      const int c = indicator[s.feet[f].foot];
      if (c < 0) {
        throw LogError(name, at, "",
                       "foot " + std::to_string(s.feet[f].foot) + " of the sample of line " +
                           std::to_string(s.line) + " has no contact indicator");
      }
      s.contact[f] = c == 1;
    }
  };
  while (std::getline(in, text)) {
    ++line;
    const Record r(name, line, text);
    if (r.size() == 0) continue;
    if (r.size() < 2) r.fail("", "record '" + r.kind() + "' has no time");
    const double t = r.number(1, "t");
    if (r.kind() == "IMU") {
      finish(line);
      if (!log.samples.empty() && !(t > log.samples.back().t)) {
        std::ostringstream os;
        os << "time " << t << " is not after the previous sample's " << log.samples.back().t;
        r.fail("t", os.str());
      }
      HartleySample s;
      s.t = t;
      s.line = line;
      readImu(r, s);
      log.samples.push_back(s);
      have_contact = have_kinematic = false;
    } else if (r.kind() == "CONTACT" || r.kind() == "KINEMATIC") {
      if (log.samples.empty() || t != log.samples.back().t) {
        r.fail("t", r.kind() + " record without an IMU record at the same time");
      }
      bool& seen = r.kind() == "CONTACT" ? have_contact : have_kinematic;
      if (seen) r.fail("", "a second " + r.kind() + " record for the same time");
      seen = true;
      if (r.kind() == "CONTACT") {
        readContact(r, indicator);
      } else {
        readKinematic(r, log.samples.back());
      }
    } else {
      r.fail("", "unknown record '" + r.kind() + "' (expected IMU, CONTACT or KINEMATIC)");
    }
  }
  finish(line);
  if (log.samples.empty()) throw LogError(name, 0, "", "no IMU record");
  return log;
}

HartleyLog readHartleyLog(const std::string& path) {
  if (const std::string why = notARegularFile(path); !why.empty()) throw LogError(path, 0, "", why);
  std::ifstream in(path);
  if (!in) throw LogError(path, 0, "", "cannot open the file");
  return parseHartleyLog(in, path);
}

}  // namespace legkit::io
