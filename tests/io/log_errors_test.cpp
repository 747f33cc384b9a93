// Every kind of bad file makes the reader throw a LogError that names the file, the line, the
// column and what was expected. The broken files are written into a temporary folder.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/log_error.hpp"
#include "io/log_reader.hpp"
#include "io/log_writer.hpp"

namespace io = legkit::io;
namespace fs = std::filesystem;

namespace {

// A small valid quadruped log with contact flags and ground truth: header on line 1, rows on
// lines 2..6 at t = 0, 0.001, ..., 0.004.
std::string validText() {
  io::Log log;
  log.layout.contact = true;
  log.layout.ground_truth = true;
  for (int i = 0; i < 5; ++i) {
    io::LogRow row;
    row.t = 0.001 * i;
    row.acc = Eigen::Vector3d(0.0, 0.0, 9.81);
    row.q.setConstant(0.1 * i);
    row.contact = {true, false, false, true};
    log.rows.push_back(row);
  }
  std::ostringstream out;
  io::writeLog(out, log);
  return out.str();
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::string join(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& line : lines) out += line + "\n";
  return out;
}

// Replaces field `column` (0-based) of line `line` (1-based).
std::string withField(const std::string& text, int line, int column, const std::string& value) {
  std::vector<std::string> ls = lines(text);
  std::string& l = ls[line - 1];
  std::size_t start = 0;
  for (int i = 0; i < column; ++i) start = l.find(',', start) + 1;
  const std::size_t end = l.find(',', start);
  l.replace(start, end == std::string::npos ? std::string::npos : end - start, value);
  return join(ls);
}

class TempDir {
 public:
  TempDir() : path_(fs::temp_directory_path() / ("legkit_io_test_" + std::to_string(getpid()))) {
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path file = path_ / name;
    std::ofstream(file, std::ios::binary) << text;
    return file.string();
  }

 private:
  fs::path path_;
};

struct Expected {
  int line;
  std::string column;
  std::string message;  // a piece of the message
};

void checkError(const TempDir& dir, const std::string& name, const std::string& text,
                const Expected& expected, const io::ReadOptions& options = {}) {
  const std::string path = dir.write(name, text);
  INFO("file " << name);
  try {
    io::readLog(path, options);
    FAIL("no error for " << name);
  } catch (const io::LogError& e) {
    INFO("message: " << e.what());
    CHECK(e.file() == path);
    CHECK(e.line() == expected.line);
    CHECK(e.column() == expected.column);
    const std::string what = e.what();
    CHECK(what.find(expected.message) != std::string::npos);
    const std::string where =
        path + (expected.line > 0 ? ":" + std::to_string(expected.line) : "") + ": ";
    CHECK(what.rfind(where, 0) == 0);
    if (!expected.column.empty()) {
      CHECK(what.find("column '" + expected.column + "'") != std::string::npos);
    }
  }
}

}  // namespace

TEST_CASE("The valid base file reads", "[57.3][log]") {
  const TempDir dir;
  const io::Log log = io::readLog(dir.write("valid.csv", validText()));
  CHECK(log.rows.size() == 5);
  CHECK(log.layout.contact);
}

TEST_CASE("Each broken file gives an error naming line and column", "[57.3][log]") {
  const TempDir dir;
  const std::string good = validText();
  // Columns: 0 t, 1-3 gyro, 4-6 acc, 7-18 q, 19-30 dq, 31-34 contact, 35-44 gt.
  checkError(dir, "non_numeric.csv", withField(good, 3, 5, "abc"),
             {3, "acc_y", "expected a number, got 'abc'"});
  checkError(dir, "trailing_text.csv", withField(good, 4, 8, "0.1x"),
             {4, "q_FL_1", "expected a number, got '0.1x'"});
  checkError(dir, "nan.csv", withField(good, 2, 3, "nan"),
             {2, "gyro_z", "expected a finite number, got 'nan'"});
  checkError(dir, "inf.csv", withField(good, 5, 20, "-inf"),
             {5, "dq_FL_1", "expected a finite number, got '-inf'"});
  checkError(dir, "overflow.csv", withField(good, 5, 1, "1e999"),
             {5, "gyro_x", "expected a finite number"});
  checkError(dir, "empty_field.csv", withField(good, 6, 10, ""),
             {6, "q_FR_0", "the field is empty"});
  checkError(dir, "bad_contact.csv", withField(good, 3, 32, "2"),
             {3, "contact_FR", "expected a contact flag 0 or 1, got '2'"});
  checkError(dir, "bad_quaternion.csv", withField(good, 4, 38, "0.5"),
             {4, "gt_qw", "expected a unit quaternion"});

  std::vector<std::string> ls = lines(good);
  {  // too few fields: the last two are cut
    std::vector<std::string> v = ls;
    v[2] = v[2].substr(0, v[2].rfind(','));
    v[2] = v[2].substr(0, v[2].rfind(','));
    checkError(dir, "too_few.csv", join(v), {3, "gt_vy", "too few fields: 43 of 45"});
  }
  {
    std::vector<std::string> v = ls;
    v[4] += ",7";
    checkError(dir, "too_many.csv", join(v), {5, "", "too many fields: 46, the header has 45"});
  }
  {  // timestamps: line 4 repeats line 3's time
    checkError(dir, "not_increasing.csv", withField(good, 4, 0, "0.001"),
               {4, "t", "timestamps must strictly increase: 0.001 follows 0.001 on line 3"});
    checkError(dir, "backwards.csv", withField(good, 5, 0, "0.0015"),
               {5, "t", "timestamps must strictly increase"});
  }
  {  // a dropped sample: t jumps from 0.002 to 0.004
    std::vector<std::string> v = ls;
    v.erase(v.begin() + 4);
    io::ReadOptions options;
    options.max_gap = 0.0015;
    checkError(dir, "gap.csv", join(v), {5, "t", "gap of 0.002 s after t = 0.002 on line 4"},
               options);
    CHECK_NOTHROW(io::readLog(dir.write("gap_allowed.csv", join(v))));  // no bound by default
  }
  {  // header problems
    checkError(dir, "unknown.csv", withField(good, 1, 7, "q_FL_O"),
               {1, "q_FL_O", "unknown column (header field 8)"});
    checkError(dir, "duplicate.csv", withField(good, 1, 2, "gyro_x"),
               {1, "gyro_x", "appears twice in the header"});
    checkError(dir, "alias_duplicate.csv", withField(good, 1, 32, "foot0_contact"),
               {1, "foot0_contact", "duplicates column 'contact_FL'"});
    checkError(dir, "empty_header_field.csv", withField(good, 1, 3, ""),
               {1, "", "header field 4 is empty"});
  }
  {  // a required column and its data removed
    std::string text;
    for (const std::string& l : ls) {
      std::vector<std::string> fields;
      std::istringstream in(l);
      for (std::string f; std::getline(in, f, ',');) fields.push_back(f);
      fields.erase(fields.begin() + 6);  // acc_z
      std::string joined;
      for (std::size_t i = 0; i < fields.size(); ++i) joined += (i ? "," : "") + fields[i];
      text += joined + "\n";
    }
    checkError(dir, "missing_acc_z.csv", text, {1, "acc_z", "missing required column"});
  }
  {  // half a ground-truth group
    std::string text;
    for (const std::string& l : ls) text += l.substr(0, l.rfind(',')) + "\n";
    checkError(dir, "partial_gt.csv", text, {1, "gt_vz", "the ground-truth group needs all"});
  }
  {
    checkError(dir, "empty.csv", "", {0, "", "no header line"});
    checkError(dir, "header_only.csv", ls[0] + "\n", {1, "", "no data rows"});
    std::vector<std::string> v = ls;
    v.insert(v.begin() + 3, "");
    checkError(dir, "blank_line.csv", join(v), {4, "", "blank line inside the data"});
    CHECK_NOTHROW(io::readLog(dir.write("trailing_blank.csv", good + "\n\n")));
  }
}

TEST_CASE("Foot columns: variances and incomplete feet", "[57.3][log]") {
  const TempDir dir;
  const std::string header =
      "t,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z,foot0_px,foot0_py,foot0_pz,foot0_var_x,"
      "foot0_var_y,foot0_var_z";
  const std::string row = "0,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,1e-4,1e-4";
  CHECK(io::readLog(dir.write("foot.csv", header + "\n" + row + "\n")).layout.num_feet == 1);
  checkError(dir, "negative_variance.csv",
             header + "\n" + row + "\n" + "0.001,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,-1e-4,1e-4\n",
             {3, "foot0_var_y", "expected a variance > 0, got '-1e-4'"});
  checkError(dir, "zero_variance.csv",
             header + "\n" + row + "\n" + "0.001,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,0,1e-4\n",
             {3, "foot0_var_y", "a zero variance claims a perfect measurement"});
  checkError(dir, "foot_without_variance.csv",
             "t,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z,foot0_px,foot0_py,foot0_pz\n0,0,0,0,0,0,0,0,"
             "0,0\n",
             {1, "foot0_var_x", "foot position columns need their variances"});
  checkError(dir, "incomplete_foot.csv", header + ",foot1_px\n" + row + ",0\n",
             {1, "foot1_py", "each foot needs _px _py _pz"});
  checkError(dir, "blank_before_header.csv", "# robot\n\n" + header + "\n" + row + "\n",
             {2, "", "blank line where the header was expected (comment lines start with '#')"});
  checkError(dir, "no_legs.csv", "t,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z\n0,0,0,0,0,0,0\n",
             {1, "q_FL_0", "a log needs joint columns"});
}

TEST_CASE("Full foot covariances must be positive definite", "[57.3][log]") {
  const TempDir dir;
  const std::string header =
      "t,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z,foot0_px,foot0_py,foot0_pz,foot0_cov_xx,"
      "foot0_cov_xy,foot0_cov_xz,foot0_cov_yy,foot0_cov_yz,foot0_cov_zz";
  const std::string good = "0,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,2e-5,0,1e-4,0,1e-4\n";
  CHECK_NOTHROW(io::readLog(dir.write("spd.csv", header + "\n" + good)));
  // Positive diagonal, symmetric by construction, but xy too large: eigenvalues 3e-4 and -1e-4.
  checkError(dir, "indefinite.csv",
             header + "\n" + good + "0.001,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,2e-4,0,1e-4,0,1e-4\n",
             {3, "foot0_cov_xy",
              "foot 0 covariance is not positive definite: |cov_xy| must be below sqrt(cov_xx "
              "cov_yy), the correlation is 2"});
  checkError(dir, "zero_cov.csv",
             header + "\n" + good + "0.001,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,0,0,0,0,1e-4\n",
             {3, "foot0_cov_yy", "expected a variance > 0"});
  // Every pair is a valid 2x2 covariance, the three together are not (correlations 0.9, 0.9,
  // -0.9): the message names the determinant, not a pair.
  checkError(dir, "indefinite_3x3.csv",
             header + "\n" + good + "0.001,0,0,0,0,0,9.81,0.2,0.1,-0.3,1,0.9,0.9,1,-0.9,1\n",
             {3, "foot0_cov_xx", "correlations xy 0.9, xz 0.9, yz -0.9 give no valid covariance"});
}

TEST_CASE("A covariance check that overflow cannot fool", "[57.3][log]") {
  // cov_xz / sqrt(cov_xx) overflows to inf in a plain Cholesky factorisation, inf * 0 then makes a
  // NaN, and a NaN pivot passes a "pivot <= 0" test: this matrix, far from positive definite, was
  // once accepted.
  const TempDir dir;
  const std::string header =
      "t,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z,foot0_px,foot0_py,foot0_pz,foot0_cov_xx,"
      "foot0_cov_xy,foot0_cov_xz,foot0_cov_yy,foot0_cov_yz,foot0_cov_zz";
  checkError(
      dir, "overflow.csv", header + "\n0,0,0,0,0,0,9.81,0,0,0,1e-300,0,1e200,1,0,1\n",
      {2, "foot0_cov_xz", "foot 0 covariance is not positive definite: |cov_xz| must be below"});
  // Extreme but valid scales still pass.
  CHECK_NOTHROW(io::readLog(dir.write(
      "scales.csv", header + "\n0,0,0,0,0,0,9.81,0,0,0,1e-300,1e-160,0,1e-10,0,1e300\n")));
}

TEST_CASE("The contact-truth group: all or nothing, flags, magnitudes", "[57.0][log]") {
  const TempDir dir;
  io::Log log;
  log.layout.contact_truth = true;
  for (int i = 0; i < 3; ++i) {
    io::LogRow row;
    row.t = 0.001 * i;
    row.gt_feet[1] = {true, 60.0, 4.0, Eigen::Vector3d(0.01, 0.0, 0.0), 0.01};
    log.rows.push_back(row);
  }
  std::ostringstream out;
  io::writeLog(out, log);
  const std::string good = out.str();
  // Columns: 0 t, 1-6 IMU, 7-30 joints, 31-34 gt_contact, 35-38 gt_fn, 39-42 gt_ft,
  // 43-54 gt_vf, 55-58 gt_slip.
  const io::Log back = io::readLog(dir.write("truth.csv", good));
  CHECK(back.layout.contact_truth);
  CHECK(back.rows.at(2).gt_feet[1].normal_force == 60.0);
  checkError(dir, "truth_flag.csv", withField(good, 3, 32, "0.5"),
             {3, "gt_contact_FR", "expected a contact flag 0 or 1, got '0.5'"});
  checkError(dir, "truth_fn.csv", withField(good, 2, 36, "-1"),
             {2, "gt_fn_FR", "expected a magnitude >= 0, got '-1'"});
  checkError(dir, "truth_ft.csv", withField(good, 4, 42, "-1e-300"),
             {4, "gt_ft_RR", "expected a magnitude >= 0"});
  checkError(dir, "truth_slip.csv", withField(good, 3, 58, "-0.2"),
             {3, "gt_slip_RR", "expected a magnitude >= 0"});
  checkError(dir, "truth_nan.csv", withField(good, 2, 44, "nan"),
             {2, "gt_vf_FL_y", "expected a finite number, got 'nan'"});
  {  // the last column (gt_slip_RR) and its data cut: half a group
    std::string text;
    for (const std::string& l : lines(good)) text += l.substr(0, l.rfind(',')) + "\n";
    checkError(dir, "truth_partial.csv", text,
               {1, "gt_slip_RR", "the contact-truth group needs gt_contact, gt_fn, gt_ft"});
  }
  {  // a single column of the group is half a group too
    io::Log plain;
    plain.rows.resize(1);
    std::ostringstream o;
    io::writeLog(o, plain);
    std::vector<std::string> ls = lines(o.str());
    ls[0] += ",gt_fn_FL";
    ls[1] += ",3";
    checkError(dir, "truth_one.csv", join(ls), {1, "gt_contact_FL", "the contact-truth group"});
  }
  // A foot past the fourth in a joint log.
  checkError(dir, "truth_foot4.csv", withField(good, 1, 31, "foot4_gt_contact"),
             {1, "", "a log with joint columns has 4 feet, but a column names foot 4"});
  // The writer refuses what the reader would.
  log.rows[2].gt_feet[3].slip_speed = -0.5;
  std::ostringstream refused;
  CHECK_THROWS_WITH(
      io::writeLog(refused, log, "mem"),
      Catch::Matchers::Contains("mem:4: column 'gt_slip_RR': cannot write a negative"));
}

TEST_CASE("One leg description per log: joints or feet, not both", "[57.3][log]") {
  io::Log log;
  log.layout.joints = true;
  log.layout.foot_columns = io::FootCovariance::kDiagonal;
  log.rows.resize(1);
  for (auto& f : log.rows[0].feet) f.cov = Eigen::Matrix3d::Identity();
  std::ostringstream out;
  io::writeLog(out, log, "mem");
  std::istringstream in(out.str());
  CHECK_THROWS_WITH(io::readLog(in, "both.csv"),
                    Catch::Matchers::Contains("both.csv:1: the log describes its legs twice"));
}

TEST_CASE("Line ends, byte-order mark, and what the reader says of bad bytes", "[57.3][log]") {
  const std::string header =
      "t,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z,foot0_px,foot0_py,"
      "foot0_pz,foot0_var_x,foot0_var_y,foot0_var_z";
  const std::string r0 = "0,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,1e-4,1e-4";
  const std::string r1 = "0.001,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,1e-4,1e-4";
  for (const std::string eol : {"\n", "\r\n", "\r"}) {
    for (const std::string bom : {"", "\xEF\xBB\xBF"}) {
      INFO("eol " << (eol == "\n"   ? "LF"
                      : eol == "\r" ? "CR"
                                    : "CRLF")
                  << ", bom " << !bom.empty());
      std::istringstream in(bom + "# a comment" + eol + header + eol + r0 + eol + r1 + eol);
      const io::Log log = io::readLog(in, "eol.csv");
      CHECK(log.rows.size() == 2);
      CHECK(log.rows[1].t == 0.001);
      CHECK(log.comments == std::vector<std::string>{"a comment"});
      CHECK(log.source == "eol.csv");
      CHECK(log.lineOfRow(1) == 4);
    }
  }
  // Underflow is not overflow; a bad field is escaped and cut.
  const auto errorOf = [&](const std::string& field) {
    std::istringstream in(header + "\n" + r0 + "\n0.001,0," + field +
                          ",0,0,0,9.81,0.2,0.1,-0.3,"
                          "1e-4,1e-4,1e-4\n");
    try {
      io::readLog(in, "bad.csv");
    } catch (const io::LogError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(errorOf("1e-400"), Catch::Matchers::Contains("underflow"));
  CHECK_THAT(errorOf("1e400"), Catch::Matchers::Contains("overflow"));
  const std::string nul = errorOf(std::string("1\0002", 3));
  CHECK_THAT(nul, Catch::Matchers::Contains("'1\\x002'"));
  const std::string huge = errorOf(std::string(100000, 'x'));
  CHECK(huge.size() < 200);
  CHECK_THAT(huge, Catch::Matchers::Contains("(100000 characters)"));
  std::istringstream garbage(std::string(50000, '\x01') + "\n0\n");
  try {
    io::readLog(garbage, "garbage.csv");
    FAIL("no error");
  } catch (const io::LogError& e) {
    CHECK(std::string(e.what()).size() < 300);
    CHECK_THAT(e.what(), Catch::Matchers::Contains("\\x01\\x01"));
  }
}

TEST_CASE("A missing file and an unwritable log are errors too", "[57.3][log]") {
  const TempDir dir;
  CHECK_THROWS_WITH(io::readLog("/nonexistent/legkit.csv"),
                    "/nonexistent/legkit.csv: cannot open the file for reading");
  io::Log log;
  log.rows.resize(2);  // both at t = 0
  std::ostringstream out;
  CHECK_THROWS_WITH(io::writeLog(out, log, "mem"),
                    Catch::Matchers::Contains("mem:3: column 't': timestamps must strictly"));
  log.rows[1].t = 1.0;
  log.rows[1].gyro.x() = std::nan("");
  CHECK_THROWS_WITH(io::writeLog(out, log, "mem"),
                    Catch::Matchers::Contains("mem:3: column 'gyro_x': cannot write a NaN"));
}

// AddressSanitizer reserves terabytes of address space and handles failed allocations its own
// way: the memory test below needs a plain allocator.
#if defined(__SANITIZE_ADDRESS__)
#define LEGKIT_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LEGKIT_TEST_ASAN 1
#endif
#endif

TEST_CASE("A log too large for memory is a LogError, not a bare bad_alloc", "[57.3][log]") {
#ifdef LEGKIT_TEST_ASAN
  SUCCEED("skipped under AddressSanitizer");
#else
  // A 4 GB file (sparse: two rows, then zeros) of 50-byte rows asks for about 86 million rows,
  // 90 GB: more than the 1 GB of address space the child process below may use.
  const TempDir dir;
  const std::string path =
      dir.write("huge.csv",
                "t,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z,foot0_px,foot0_py,foot0_pz,foot0_var_x,"
                "foot0_var_y,foot0_var_z\n0,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,1e-4,1e-4\n"
                "0.001,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,1e-4,1e-4\n");
  fs::resize_file(path, 4'000'000'000);
  int pipe_ends[2];
  REQUIRE(pipe(pipe_ends) == 0);
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {  // no Catch2 macros in here: report through the pipe and the exit code
    close(pipe_ends[0]);
    const rlimit limit{1ul << 30, 1ul << 30};
    setrlimit(RLIMIT_AS, &limit);
    std::string message = "no error";
    int code = 1;
    try {
      io::readLog(path);
    } catch (const io::LogError& e) {
      message = e.what();
      code = 0;
    } catch (const std::exception& e) {
      message = std::string("not a LogError: ") + e.what();
    }
    const ssize_t written = write(pipe_ends[1], message.data(), message.size());
    _exit(written < 0 ? 2 : code);
  }
  close(pipe_ends[1]);
  std::string message;
  char buffer[512];
  for (ssize_t n; (n = read(pipe_ends[0], buffer, sizeof buffer)) > 0;) message.append(buffer, n);
  close(pipe_ends[0]);
  int status = 0;
  waitpid(child, &status, 0);
  INFO("child said: " << message);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  CHECK_THAT(message,
             Catch::Matchers::StartsWith(path + ":3: the log is too large for this "
                                                "machine's memory (4000000000 bytes, 1 row "
                                                "read;"));
#endif
}
