// A log written by writeLog reads back exactly (==, no tolerance), for any layout and any finite
// values, including subnormals, huge magnitudes and negative zero.
#include <rapidcheck/catch.h>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

#include "io/log_columns.hpp"
#include "io/log_reader.hpp"
#include "io/log_writer.hpp"

namespace io = legkit::io;

namespace {

// Any finite double, drawn from its bit pattern so that every exponent is as likely.
rc::Gen<double> anyFiniteDouble() {
  return rc::gen::suchThat(rc::gen::map(rc::gen::arbitrary<std::uint64_t>(),
                                        [](std::uint64_t bits) {
                                          double x;
                                          std::memcpy(&x, &bits, sizeof x);
                                          return x;
                                        }),
                           [](double x) { return std::isfinite(x); });
}

// Any positive finite double (a variance the reader takes).
rc::Gen<double> positiveDouble() {
  return rc::gen::map(rc::gen::suchThat(anyFiniteDouble(), [](double x) { return x != 0.0; }),
                      [](double x) { return std::abs(x); });
}

io::LogLayout genLayout() {
  io::LogLayout layout;
  layout.joints = *rc::gen::arbitrary<bool>();
  // One leg description per log: joints, or foot columns.
  const int covariance = layout.joints ? 0 : *rc::gen::inRange(1, 3);
  layout.foot_columns = static_cast<io::FootCovariance>(covariance);
  layout.num_feet = layout.joints ? io::kNumLegs : *rc::gen::inRange(1, io::kMaxFeet + 1);
  layout.torque = layout.joints && *rc::gen::arbitrary<bool>();
  layout.force = *rc::gen::arbitrary<bool>();
  layout.contact = *rc::gen::arbitrary<bool>();
  layout.ground_truth = *rc::gen::arbitrary<bool>();
  layout.contact_truth = *rc::gen::arbitrary<bool>();
  return layout;
}

io::LogRow genRow(const std::vector<io::Column>& columns, double t) {
  io::LogRow row;
  for (const io::Column& c : columns) {
    switch (c.field) {
      case io::Field::kTime:
        setValue(row, c, t);
        break;
      case io::Field::kContact:
      case io::Field::kGtContact:
        setValue(row, c, *rc::gen::inRange(0, 2));
        break;
      case io::Field::kGtFn:
      case io::Field::kGtFt:
      case io::Field::kGtSlip:  // magnitudes >= 0; -0.0 is >= 0 too and keeps its sign
        setValue(
            row, c,
            *rc::gen::oneOf(rc::gen::map(anyFiniteDouble(), [](double x) { return std::abs(x); }),
                            rc::gen::just(-0.0)));
        break;
      case io::Field::kFootVar:
        setValue(row, c, std::abs(*positiveDouble()));
        break;
      case io::Field::kFootCov: {
        const bool diagonal = c.index == 0 || c.index == 3 || c.index == 5;
        setValue(row, c, diagonal ? *positiveDouble() : *anyFiniteDouble());
        break;
      }
      case io::Field::kGtQ:
        break;  // below: a unit quaternion
      default:
        setValue(row, c, *anyFiniteDouble());
        break;
    }
  }
  // The reader takes only positive definite covariances: keep each off-diagonal entry within 0.3
  // of the smaller variance (diagonally dominant), whatever its magnitude.
  for (io::FootKinematics& f : row.feet) {
    for (int i = 0; i < 3; ++i) {
      for (int j = i + 1; j < 3; ++j) {
        const double bound = 0.3 * std::min(f.cov(i, i), f.cov(j, j));
        if (!(std::abs(f.cov(i, j)) <= bound))
          f.cov(i, j) = std::copysign(0.5 * bound, f.cov(i, j));
        f.cov(j, i) = f.cov(i, j);
      }
    }
  }
  const auto angle = *rc::gen::inRange(-3141, 3142);
  Eigen::Vector3d axis(*rc::gen::inRange(-100, 101), *rc::gen::inRange(-100, 101), 1.0);
  row.gt_q = Eigen::Quaterniond(Eigen::AngleAxisd(angle * 1e-3, axis.normalized()));
  return row;
}

}  // namespace

TEST_CASE("A written log reads back exactly", "[57.3][log]") {
  rc::prop("round trip of random rows in a random layout", [] {
    io::Log log;
    log.layout = genLayout();
    log.comments = {"legkit round-trip test", ""};
    const std::vector<io::Column> columns = io::columnsOf(log.layout);
    const int n = *rc::gen::inRange(1, 12);
    double t = *rc::gen::inRange(-1000000, 1000000) * 1e-3;
    for (int i = 0; i < n; ++i) {
      log.rows.push_back(genRow(columns, t));
      t = std::nextafter(t, INFINITY) + *rc::gen::inRange(0, 5000) * 1e-4;
    }
    if (!log.layout.ground_truth) {
      for (io::LogRow& row : log.rows) row.gt_q = Eigen::Quaterniond::Identity();
    }

    std::stringstream file;
    io::writeLog(file, log);
    const io::Log back = io::readLog(file, "round-trip");
    RC_ASSERT(back.layout == log.layout);
    RC_ASSERT(back.comments == log.comments);
    RC_ASSERT(back.rows.size() == log.rows.size());
    for (std::size_t i = 0; i < log.rows.size(); ++i) {
      RC_ASSERT(io::exactlyEqual(back.rows[i], log.rows[i]));
      for (const io::Column& c : columns) {  // also the sign of zero
        RC_ASSERT(std::signbit(valueOf(back.rows[i], c)) == std::signbit(valueOf(log.rows[i], c)));
      }
    }
  });
}

TEST_CASE("Column order and per-foot spellings are free", "[57.3][log]") {
  // A two-footed robot's log with columns in an unusual order, the foot-number spelling.
  const std::string text =
      "# biped\n"
      "foot1_contact,t,foot0_px,foot0_py,foot0_pz,foot0_cov_xx,foot0_cov_xy,foot0_cov_xz,"
      "foot0_cov_yy,foot0_cov_yz,foot0_cov_zz,foot1_px,foot1_py,foot1_pz,foot1_cov_xx,"
      "foot1_cov_xy,foot1_cov_xz,foot1_cov_yy,foot1_cov_yz,foot1_cov_zz,acc_x,acc_y,acc_z,"
      "gyro_x,gyro_y,gyro_z,foot0_contact\n"
      "1,0.5,0.1,0.2,-0.8,1e-4,1e-6,0,2e-4,0,3e-4,0.1,-0.2,-0.8,1e-4,0,0,1e-4,0,1e-4,0,0,9.81,"
      "0.01,0.02,0.03,0\n";
  std::istringstream in(text);
  const io::Log log = io::readLog(in, "biped.csv");
  CHECK_FALSE(log.layout.joints);
  CHECK(log.layout.num_feet == 2);
  CHECK(log.layout.foot_columns == io::FootCovariance::kFull);
  CHECK(log.layout.contact);
  REQUIRE(log.rows.size() == 1);
  const io::LogRow& row = log.rows[0];
  CHECK(row.t == 0.5);
  CHECK(row.contact[1]);
  CHECK_FALSE(row.contact[0]);
  CHECK(row.feet[0].cov(0, 1) == 1e-6);
  CHECK(row.feet[0].cov(1, 0) == 1e-6);  // the upper triangle fills both halves
  CHECK(row.feet[1].p_body.y() == -0.2);
  CHECK(row.acc.z() == 9.81);
  CHECK(log.comments == std::vector<std::string>{"biped"});

  // Written back in canonical order, it reads back the same.
  std::stringstream again;
  io::writeLog(again, log);
  CHECK(again.str().find("\nt,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z,foot0_contact,foot1_contact,"
                         "foot0_px,") != std::string::npos);
  const io::Log back = io::readLog(again, "again");
  CHECK(io::exactlyEqual(back.rows[0], row));
}

TEST_CASE("The quadruped header names every column of the chapter's format", "[57.3][log]") {
  io::LogLayout layout;
  layout.torque = layout.force = layout.contact = layout.ground_truth = true;
  std::vector<std::string> names;
  for (const io::Column& c : io::columnsOf(layout)) names.push_back(c.name);
  REQUIRE(names.size() == 1 + 3 + 3 + 12 * 3 + 4 + 4 + 10);
  CHECK(names[0] == "t");
  CHECK(names[1] == "gyro_x");
  CHECK(names[4] == "acc_x");
  CHECK(names[7] == "q_FL_0");
  CHECK(names[18] == "q_RR_2");
  CHECK(names[19] == "dq_FL_0");
  CHECK(names[31] == "tau_FL_0");
  CHECK(names[43] == "force_FL");
  CHECK(names[47] == "contact_FL");
  CHECK(names[50] == "contact_RR");
  CHECK(names[51] == "gt_px");
  CHECK(names[54] == "gt_qw");
  CHECK(names[60] == "gt_vz");
}

TEST_CASE("The contact-truth columns: names, order and both spellings", "[57.0][log]") {
  io::LogLayout layout;
  layout.contact_truth = true;
  std::vector<std::string> names;
  for (const io::Column& c : io::columnsOf(layout)) names.push_back(c.name);
  REQUIRE(names.size() == 1 + 3 + 3 + 12 * 2 + 7 * 4);
  CHECK(names[31] == "gt_contact_FL");
  CHECK(names[35] == "gt_fn_FL");
  CHECK(names[39] == "gt_ft_FL");
  CHECK(names[43] == "gt_vf_FL_x");
  CHECK(names[54] == "gt_vf_RR_z");
  CHECK(names[55] == "gt_slip_FL");
  CHECK(names[58] == "gt_slip_RR");

  // A foot-column log spells them foot<k>_gt_..; the values land in LogRow::gt_feet.
  const std::string text =
      "t,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z,foot0_px,foot0_py,foot0_pz,foot0_var_x,"
      "foot0_var_y,foot0_var_z,foot0_gt_contact,foot0_gt_fn,foot0_gt_ft,foot0_gt_vf_x,"
      "foot0_gt_vf_y,foot0_gt_vf_z,foot0_gt_slip\n"
      "0,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,1e-4,1e-4,1,80.5,12.25,0.5,-0.25,0.125,0.5\n";
  std::istringstream in(text);
  const io::Log log = io::readLog(in, "truth.csv");
  CHECK(log.layout.contact_truth);
  CHECK(log.layout.num_feet == 1);
  const io::FootTruth& foot = log.rows.at(0).gt_feet[0];
  CHECK(foot.contact);
  CHECK(foot.normal_force == 80.5);
  CHECK(foot.tangential_force == 12.25);
  CHECK(foot.velocity == Eigen::Vector3d(0.5, -0.25, 0.125));
  CHECK(foot.slip_speed == 0.5);
  std::stringstream again;
  io::writeLog(again, log);
  CHECK(again.str().find(",foot0_gt_contact,foot0_gt_fn,foot0_gt_ft,foot0_gt_vf_x,") !=
        std::string::npos);
  CHECK(io::exactlyEqual(io::readLog(again, "again").rows.at(0), log.rows[0]));
  // exactlyEqual sees every field of the group.
  io::LogRow other = log.rows[0];
  other.gt_feet[0].velocity.z() = 0.0;
  CHECK_FALSE(io::exactlyEqual(other, log.rows[0]));
  other = log.rows[0];
  other.gt_feet[0].contact = false;
  CHECK_FALSE(io::exactlyEqual(other, log.rows[0]));
  io::LogLayout without = log.layout;
  without.contact_truth = false;
  CHECK(without != log.layout);
}

TEST_CASE("Whatever the reader accepts, it reads back the same once written", "[57.3][log]") {
  // The other direction of the round trip: files legkit did not write, in every form the reader
  // takes. read -> write -> read must give the same log, and writing it again the same bytes.
  const std::string header =
      "t,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z,foot0_px,foot0_py,"
      "foot0_pz,foot0_var_x,foot0_var_y,foot0_var_z";
  const std::string r0 = "0,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,1e-4,1e-4";
  const std::string r1 =
      " +1e-3 ,-0,4.9406564584124654e-324,1e308,0,0,9.81,0.2,0.1,-0.3,"
      "2.2250738585072014e-308,1e-4,1e-4";
  const std::vector<std::string> texts = {
      header + "\n" + r0 + "\n" + r1,                                // no final newline
      "\xEF\xBB\xBF" + header + "\r\n" + r0 + "\r\n" + r1 + "\r\n",  // BOM, CRLF
      "#\r#  two spaces\r# tab\there\r" + header + "\r" + r0 + "\r" + r1 + "\r\r",  // old Mac
      "# a\r# b\n" + header + "\n" + r0 + "\n" + r1 + "\n\n\n",  // CR ends a comment line too
      "\xEF\xBB\xBF# \xEF\xBB\xBF after a BOM\n#\x01\x7f\xff bytes\n" + header + "\n" + r0 + "\n" +
          r1 + "\n",
  };
  for (const std::string& text : texts) {
    INFO("input: " << text);
    std::istringstream in(text);
    const io::Log log = io::readLog(in, "odd.csv");
    std::stringstream once;
    io::writeLog(once, log);
    const io::Log back = io::readLog(once, "once.csv");
    CHECK(back.layout == log.layout);
    CHECK(back.comments == log.comments);
    REQUIRE(back.rows.size() == log.rows.size());
    for (std::size_t k = 0; k < log.rows.size(); ++k)
      CHECK(io::exactlyEqual(back.rows[k], log.rows[k]));
    std::ostringstream twice;
    io::writeLog(twice, back);
    CHECK(twice.str() == once.str());
  }
  // A CR ends a line, so no comment the reader returns holds one; the writer refuses a comment
  // that does (it would come back as two).
  std::istringstream two(texts[3]);
  CHECK(io::readLog(two, "two.csv").comments == std::vector<std::string>{"a", "b"});
}

TEST_CASE("A byte-order mark before the header: the first column is still t", "[57.3][log]") {
  std::istringstream in(
      "\xEF\xBB\xBFt,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z,foot0_px,foot0_py,"
      "foot0_pz,foot0_var_x,foot0_var_y,foot0_var_z\n"
      "0.25,1,2,3,4,5,6,0.2,0.1,-0.3,1e-4,1e-4,1e-4\n");
  const io::Log log = io::readLog(in, "bom.csv");
  REQUIRE(log.rows.size() == 1);
  CHECK(log.rows[0].t == 0.25);
  CHECK(log.rows[0].gyro.x() == 1.0);
  CHECK(log.lineOfRow(0) == 2);
}

TEST_CASE("Log::source and lineOfRow", "[57.3][log]") {
  // Read: the rows' own lines, whatever ends them; comments count.
  std::istringstream in(
      "# one\r# two\rt,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z,foot0_px,foot0_py,"
      "foot0_pz,foot0_var_x,foot0_var_y,foot0_var_z\r\n"
      "0,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,1e-4,1e-4\r\n"
      "1,0,0,0,0,0,9.81,0.2,0.1,-0.3,1e-4,1e-4,1e-4\r\n\r\n");
  const io::Log log = io::readLog(in, "robot.csv");
  CHECK(log.source == "robot.csv");
  CHECK(log.lineOfRow(0) == 4);
  CHECK(log.lineOfRow(1) == 5);
  // Made in memory: as the writer would write it.
  io::Log made;
  made.comments = {"x"};
  made.rows.resize(3);
  CHECK(made.source.empty());
  CHECK(made.lineOfRow(2) == 5);
}
