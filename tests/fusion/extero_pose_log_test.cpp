// The pose file (estimation/fusion/pose_log.hpp): round trip, every malformed row named by line
// and column, the writer's checks, and no crash on any bytes.
#include <rapidcheck.h>
#include <rapidcheck/catch.h>
#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "estimation/fusion/pose_log.hpp"
#include "io/log_error.hpp"

using legkit::fusion::Matrix6d;
using legkit::fusion::PoseMeasurement;
using legkit::fusion::readPoseLog;
using legkit::fusion::writePoseLog;
using legkit::io::LogError;

namespace {

std::vector<PoseMeasurement> somePoses(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<PoseMeasurement> poses;
  for (int k = 0; k < n; ++k) {
    PoseMeasurement z;
    z.t = 0.1 * k + 1e-3 * normal(rng) * 0.1;
    z.t_arrival = z.t + 0.08;
    z.R_MB = lie::SO3d::Exp(Eigen::Vector3d(normal(rng), normal(rng), normal(rng)));
    z.p_MB = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * 10.0;
    Matrix6d A = Matrix6d::Random() * 0.1;
    z.cov = A * A.transpose() + 1e-4 * Matrix6d::Identity();
    z.valid = k % 3 != 1;
    poses.push_back(z);
  }
  return poses;
}

std::string text(const std::vector<PoseMeasurement>& poses) {
  std::ostringstream out;
  writePoseLog(out, poses, {"simulated", "seed 1"});
  return out.str();
}

std::vector<PoseMeasurement> parse(const std::string& s) {
  std::istringstream in(s);
  return readPoseLog(in, "poses.csv");
}

// Replaces field `column` (0-based) of line `line` (0-based, in the text) by `value`.
std::string withField(const std::string& s, int line, int column, const std::string& value) {
  std::vector<std::string> lines;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::vector<std::string> fields;
  std::istringstream row(lines.at(line));
  for (std::string f; std::getline(row, f, ',');) fields.push_back(f);
  fields.at(column) = value;
  std::string joined;
  for (std::size_t i = 0; i < fields.size(); ++i) joined += (i ? "," : "") + fields[i];
  lines.at(line) = joined;
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

std::string errorOf(const std::string& s) {
  try {
    parse(s);
  } catch (const LogError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("pose file: write then read gives the same poses", "[fusion][extero]") {
  const auto poses = somePoses(50, 1);
  const std::string s = text(poses);
  const auto back = parse(s);
  REQUIRE(back.size() == poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    CHECK(back[k].t == poses[k].t);
    CHECK(back[k].t_arrival == poses[k].t_arrival);
    CHECK(back[k].p_MB == poses[k].p_MB);
    CHECK(back[k].cov == poses[k].cov);  // the upper triangle, mirrored
    CHECK(back[k].valid == poses[k].valid);
    // The attitude goes through a quaternion: equal to rounding.
    CHECK((back[k].R_MB.matrix() - poses[k].R_MB.matrix()).cwiseAbs().maxCoeff() <=
          legkit::fusion::kPoseLogAttitudeRoundTrip);
  }
  // A file read back and written again is a fixed point of read: the same numbers.
  const auto again = parse(text(back));
  for (std::size_t k = 0; k < back.size(); ++k) {
    CHECK(again[k].p_MB == back[k].p_MB);
    CHECK((again[k].R_MB.matrix() - back[k].R_MB.matrix()).cwiseAbs().maxCoeff() <=
          legkit::fusion::kPoseLogAttitudeRoundTrip);
  }
  // The header is the documented one and comments come first.
  CHECK(s.rfind("# simulated\n# seed 1\nt,t_arrival,px,py,pz,qw,qx,qy,qz,c00,c01,", 0) == 0);
}

TEST_CASE("pose file: CR LF line ends, a byte-order mark and spaces are read", "[fusion][extero]") {
  std::string s = text(somePoses(3, 2));
  std::string crlf = "\xEF\xBB\xBF";
  for (char c : s) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  CHECK(parse(crlf).size() == 3);
  CHECK(parse(withField(s, 3, 2, "  1.5 "))[0].p_MB.x() == 1.5);
}

TEST_CASE("pose file: every malformed row is named by line and column", "[fusion][extero]") {
  const std::string s = text(somePoses(3, 3));  // lines: 2 comments, header (3), rows 4..6
  const int row = 3;                            // 0-based index of line 4, the first row
  struct Case {
    std::string name, file, expected;
  };
  // Built by hand: the first row without its last field, a blank line after the first row.
  const std::size_t row_end = s.find('\n', s.find('\n', s.find("valid")) + 1);
  std::string short_row = s;
  short_row.erase(s.rfind(',', row_end), row_end - s.rfind(',', row_end));
  std::string blank = s;
  blank.insert(row_end + 1, "\n");
  std::vector<Case> cases = {
      {"wrong header name", withField(s, 2, 2, "x"), "poses.csv:3: header field 3: expected 'px'"},
      {"header too long", withField(s, 2, 30, "valid,extra"),
       "poses.csv:3: expected a header of 31 columns, got 32"},
      {"empty field", withField(s, row, 30, ""),
       "poses.csv:4: column 'valid': expected a number, the field is empty"},
      {"too few fields", short_row, "poses.csv:4: expected 31 fields, got 30"},
      {"too many fields", withField(s, row + 1, 30, "1,1"),
       "poses.csv:5: expected 31 fields, got 32"},
      {"not a number", withField(s, row, 2, "abc"),
       "poses.csv:4: column 'px': expected a number, got 'abc'"},
      {"NaN", withField(s, row, 3, "nan"), "poses.csv:4: column 'py': expected a finite number"},
      {"inf", withField(s, row, 4, "-inf"), "poses.csv:4: column 'pz': expected a finite number"},
      {"overflow", withField(s, row, 0, "1e999"),
       "poses.csv:4: column 't': expected a finite number, got '1e999' (overflow"},
      {"time going back", withField(s, row + 1, 0, "-5"),
       "poses.csv:5: column 't': expected a time after the previous pose's"},
      {"same time",
       withField(
           withField(withField(withField(s, row + 1, 0, "7"), row + 1, 1, "8"), row + 2, 0, "7"),
           row + 2, 1, "8"),
       "poses.csv:6: column 't': expected a time after the previous pose's 7, got 7"},
      {"arrival before stamp", withField(s, row, 1, "-1"),
       "poses.csv:4: column 't_arrival': expected t_arrival >= t"},
      {"unnormalised quaternion", withField(s, row, 5, "3"),
       "poses.csv:4: column 'qw': expected a unit quaternion qw..qz, its norm is"},
      {"non-SPD covariance", withField(s, row + 2, 9, "-1"),
       "poses.csv:6: column 'c00': expected a positive definite covariance"},
      {"valid flag 2", withField(s, row, 30, "2"),
       "poses.csv:4: column 'valid': expected a valid flag 0 or 1, got '2'"},
      {"valid flag 0.5", withField(s, row, 30, "0.5"),
       "poses.csv:4: column 'valid': expected a valid flag 0 or 1, got '0.5'"},
  };
  cases.push_back({"blank line inside", blank, "poses.csv:5: blank line inside the data"});
  cases.push_back({"empty file", "", "poses.csv: no header line (the file is empty)"});
  cases.push_back(
      {"header only", s.substr(0, s.find('\n', s.find("valid")) + 1), "poses.csv:3: no data rows"});
  cases.push_back({"binary", std::string("t,\0\xff", 4),
                   "poses.csv:1: header field 2: expected 't_arrival', got '\\x00\\xff'"});
  for (const auto& c : cases) {
    INFO(c.name);
    const std::string error = errorOf(c.file);
    INFO(error);
    CHECK(error.rfind(c.expected, 0) == 0);
  }
  CHECK_THROWS_WITH(readPoseLog("/nonexistent/poses.csv"),
                    "/nonexistent/poses.csv: cannot open the file for reading");
}

TEST_CASE("pose file: the writer refuses what the reader would and checks its writes",
          "[fusion][extero]") {
  auto poses = somePoses(4, 4);
  std::ostringstream out;
  auto bad = poses;
  bad[2].p_MB.y() = std::nan("");
  CHECK_THROWS_WITH(writePoseLog(out, bad, {}, "w.csv"),
                    "w.csv:4: column 'py': pose 2: expected a finite number");
  bad = poses;
  bad[1].cov(3, 3) = -1.0;
  CHECK_THROWS_WITH(
      writePoseLog(out, bad, {"c"}, "w.csv"),
      Catch::StartsWith("w.csv:4: column 'c00': pose 1: expected a positive definite"));
  bad = poses;
  bad[3].t = bad[2].t;
  CHECK_THROWS_WITH(writePoseLog(out, bad, {}, "w.csv"),
                    Catch::StartsWith("w.csv:5: column 't': pose 3: expected a time after"));
  bad = poses;
  bad[0].t_arrival = bad[0].t - 0.01;
  CHECK_THROWS_WITH(writePoseLog(out, bad, {}, "w.csv"),
                    Catch::StartsWith("w.csv:2: column 't_arrival': pose 0"));
  CHECK_THROWS_WITH(writePoseLog(out, {}, {}, "w.csv"), Catch::StartsWith("w.csv: no poses"));
  CHECK_THROWS_WITH(writePoseLog(out, poses, {"two\nlines"}, "w.csv"),
                    "w.csv:1: a comment may not contain a line end");
  CHECK(out.str().empty());  // nothing was written by a refused call
  CHECK_THROWS_WITH(writePoseLog("/nonexistent/dir/p.csv", poses),
                    "/nonexistent/dir/p.csv: cannot open the file for writing");
  if (std::ifstream("/dev/full").good()) {
    CHECK_THROWS_WITH(writePoseLog("/dev/full", somePoses(2000, 5)),
                      Catch::Contains("/dev/full: write error"));
  }
}

TEST_CASE("pose file: any bytes give poses or a LogError, never a crash", "[fusion][extero]") {
  const std::string valid = text(somePoses(3, 6));
  const auto readsOrRefuses = [](const std::string& s) {
    try {
      const auto poses = parse(s);
      RC_ASSERT(!poses.empty());
      for (std::size_t k = 1; k < poses.size(); ++k) RC_ASSERT(poses[k].t > poses[k - 1].t);
      // Whatever is accepted is written back and read again to the same poses.
      const auto again = parse(text(poses));
      RC_ASSERT(again.size() == poses.size());
      for (std::size_t k = 0; k < poses.size(); ++k) {
        RC_ASSERT(again[k].t == poses[k].t);
        RC_ASSERT(again[k].p_MB == poses[k].p_MB);
        RC_ASSERT(again[k].cov == poses[k].cov);
        RC_ASSERT(again[k].valid == poses[k].valid);
        RC_ASSERT((again[k].R_MB.matrix() - poses[k].R_MB.matrix()).cwiseAbs().maxCoeff() <=
                  legkit::fusion::kPoseLogAttitudeRoundTrip);
      }
    } catch (const LogError&) {
    }
  };
  rc::prop("arbitrary bytes", [&](const std::string& s) { readsOrRefuses(s); });
  rc::prop("one byte of a valid file changed", [&] {
    const auto at = *rc::gen::inRange<std::size_t>(0, valid.size());
    const auto byte = *rc::gen::arbitrary<char>();
    std::string s = valid;
    s[at] = byte;
    readsOrRefuses(s);
  });
  rc::prop("a valid file cut anywhere", [&] {
    const auto at = *rc::gen::inRange<std::size_t>(0, valid.size());
    readsOrRefuses(valid.substr(0, at));
  });
}
