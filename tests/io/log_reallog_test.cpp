// The columns a real robot's log needs (issue 14): foot velocities, a pose-only ground truth, a
// ground-truth validity flag, generic joints. Each reads back exactly, and each way of getting
// them wrong is a LogError naming the line, the column and what was expected.
#include <rapidcheck/catch.h>
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "io/log_columns.hpp"
#include "io/log_error.hpp"
#include "io/log_reader.hpp"
#include "io/log_writer.hpp"

namespace io = legkit::io;

namespace {

// Any finite double over many magnitudes, negative zero included.
rc::Gen<double> finiteDouble() {
  return rc::gen::oneOf(
      rc::gen::map(rc::gen::inRange(-1000000, 1000001), [](int x) { return x * 1.234567e-3; }),
      rc::gen::map(rc::gen::inRange(-300, 301), [](int e) { return std::ldexp(1.7, e * 3); }),
      rc::gen::just(-0.0), rc::gen::just(5e-324));
}

// One of the three leg descriptions, with the new groups where they may go.
io::LogLayout genLayout() {
  io::LogLayout layout;
  const int legs = *rc::gen::inRange(0, 3);  // 0 quadruped joints, 1 foot columns, 2 generic
  layout.joints = legs == 0;
  layout.foot_columns = legs == 1 ? io::FootCovariance::kDiagonal : io::FootCovariance::kNone;
  layout.num_joints = legs == 2 ? *rc::gen::inRange(1, io::kMaxJoints + 1) : 0;
  layout.num_feet = legs == 0 ? io::kNumLegs : *rc::gen::inRange(1, io::kMaxFeet + 1);
  layout.foot_velocity = legs == 1 && *rc::gen::arbitrary<bool>();
  layout.contact = *rc::gen::arbitrary<bool>();
  layout.ground_truth = *rc::gen::arbitrary<bool>();
  layout.gt_velocity = !layout.ground_truth || *rc::gen::arbitrary<bool>();
  layout.gt_valid = layout.ground_truth && *rc::gen::arbitrary<bool>();
  // Generic joints without per-foot columns say nothing of the feet (the robot's description
  // does): such a log reads back with the default count of one.
  if (legs == 2 && !layout.contact) layout.num_feet = 1;
  return layout;
}

io::LogRow genRow(const io::LogLayout& layout, const std::vector<io::Column>& columns, double t) {
  io::LogRow row;
  for (const io::Column& c : columns) {
    if (c.field == io::Field::kTime) {
      setValue(row, c, t);
    } else if (c.field == io::Field::kContact || c.field == io::Field::kGtValid) {
      setValue(row, c, *rc::gen::inRange(0, 2));
    } else if (c.field == io::Field::kFootVar) {
      setValue(row, c, 1e-6 + std::abs(*finiteDouble()));
    } else if (c.field != io::Field::kGtQ) {
      setValue(row, c, *finiteDouble());
    }
  }
  // A valid row's truth is a unit quaternion; a dropout row's may be anything finite (zeros here).
  if (!layout.ground_truth) return row;
  if (row.gt_valid) {
    const int angle = *rc::gen::inRange(-3141, 3142);
    row.gt_q = Eigen::Quaterniond(Eigen::AngleAxisd(angle * 1e-3, Eigen::Vector3d::UnitZ()));
  } else {
    row.gt_q.coeffs() << *finiteDouble(), 0.0, *finiteDouble(), 0.0;
  }
  return row;
}

std::string write(const io::Log& log) {
  std::ostringstream out;
  io::writeLog(out, log, "mem");
  return out.str();
}

// The error reading `text`: line, column and a piece of the message.
void checkError(const std::string& text, int line, const std::string& column,
                const std::string& message) {
  std::istringstream in(text);
  try {
    io::readLog(in, "real.csv");
    FAIL("no error for\n" << text);
  } catch (const io::LogError& e) {
    INFO("message: " << e.what());
    CHECK(e.line() == line);
    CHECK(e.column() == column);
    CHECK(std::string(e.what()).find(message) != std::string::npos);
  }
}

const std::string kImu = "t,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z";
const std::string kImuRow = "0,0,0,0,0,0,9.81";
const std::string kFoot0 = "foot0_px,foot0_py,foot0_pz,foot0_var_x,foot0_var_y,foot0_var_z";
const std::string kFoot0Row = "0.2,0.1,-0.3,1e-4,1e-4,1e-4";
const std::string kPose = "gt_px,gt_py,gt_pz,gt_qw,gt_qx,gt_qy,gt_qz";

}  // namespace

TEST_CASE("The new columns read back exactly in every layout", "[57.0][log]") {
  rc::prop("round trip of random rows", [] {
    io::Log log;
    log.layout = genLayout();
    const std::vector<io::Column> columns = io::columnsOf(log.layout);
    const int n = *rc::gen::inRange(1, 8);
    for (int i = 0; i < n; ++i) log.rows.push_back(genRow(log.layout, columns, 0.01 * i));
    std::istringstream in(write(log));
    const io::Log back = io::readLog(in, "round-trip");
    RC_ASSERT(back.layout == log.layout);
    RC_ASSERT(back.rows.size() == log.rows.size());
    for (std::size_t i = 0; i < log.rows.size(); ++i) {
      RC_ASSERT(io::exactlyEqual(back.rows[i], log.rows[i]));
    }
  });
}

TEST_CASE("exactlyEqual sees each new field", "[57.0][log]") {
  const io::LogRow a;
  io::LogRow b = a;
  REQUIRE(io::exactlyEqual(a, b));
  b.feet[5].v_body.z() = 1e-300;
  CHECK_FALSE(io::exactlyEqual(a, b));
  b = a;
  b.joint_q(23) = -0.5;
  CHECK_FALSE(io::exactlyEqual(a, b));
  b = a;
  b.joint_dq(0) = 2.0;
  CHECK_FALSE(io::exactlyEqual(a, b));
  b = a;
  b.gt_valid = false;
  CHECK_FALSE(io::exactlyEqual(a, b));
}

TEST_CASE("The writer's columns for the new groups, in order", "[57.0][log]") {
  io::LogLayout layout;
  layout.joints = false;
  layout.num_joints = 2;
  layout.num_feet = 2;
  layout.contact = true;
  layout.ground_truth = true;
  layout.gt_velocity = false;
  layout.gt_valid = true;
  std::vector<std::string> names;
  for (const io::Column& c : io::columnsOf(layout)) names.push_back(c.name);
  CHECK(names == std::vector<std::string>{
                     "t",         "gyro_x",        "gyro_y",        "gyro_z",   "acc_x",
                     "acc_y",     "acc_z",         "joint0_q",      "joint1_q", "joint0_dq",
                     "joint1_dq", "foot0_contact", "foot1_contact", "gt_px",    "gt_py",
                     "gt_pz",     "gt_qw",         "gt_qx",         "gt_qy",    "gt_qz",
                     "gt_valid"});
  layout = io::LogLayout{};
  layout.joints = false;
  layout.foot_columns = io::FootCovariance::kDiagonal;
  layout.num_feet = 1;
  layout.foot_velocity = true;
  names.clear();
  for (const io::Column& c : io::columnsOf(layout)) names.push_back(c.name);
  CHECK(names == std::vector<std::string>{"t", "gyro_x", "gyro_y", "gyro_z", "acc_x", "acc_y",
                                          "acc_z", "foot0_px", "foot0_py", "foot0_pz",
                                          "foot0_var_x", "foot0_var_y", "foot0_var_z", "foot0_vx",
                                          "foot0_vy", "foot0_vz"});
}

TEST_CASE("A foot-column log with foot velocities", "[57.0][log]") {
  std::istringstream in(kImu + "," + kFoot0 + ",foot0_vz,foot0_vx,foot0_vy\n" + kImuRow + "," +
                        kFoot0Row + ",-0.5,0.25,0.125\n");
  const io::Log log = io::readLog(in, "real.csv");
  CHECK(log.layout.foot_velocity);
  CHECK(log.rows[0].feet[0].v_body == Eigen::Vector3d(0.25, 0.125, -0.5));

  checkError(kImu + "," + kFoot0 + ",foot0_vx,foot0_vy\n" + kImuRow + "," + kFoot0Row + ",0,0\n", 1,
             "foot0_vz", "foot velocity columns need _vx _vy _vz for every foot");
  // Two feet, the second without velocities.
  const std::string foot1 = "foot1_px,foot1_py,foot1_pz,foot1_var_x,foot1_var_y,foot1_var_z";
  checkError(kImu + "," + kFoot0 + "," + foot1 + ",foot0_vx,foot0_vy,foot0_vz\n", 1, "foot1_vx",
             "for every foot");
  // Velocities of a foot the log does not give the position of.
  checkError(kImu + "," + kFoot0 + ",foot1_vx,foot1_vy,foot1_vz\n", 1, "foot1_px",
             "each foot needs _px _py _pz");
  // Foot velocities are not a leg description.
  checkError(kImu + ",foot0_vx,foot0_vy,foot0_vz\n", 1, "foot0_px",
             "foot velocity columns (foot<k>_vx..) need the foot position columns");
}

TEST_CASE("A pose-only truth and the gt_valid flag", "[57.0][log]") {
  const std::string header = kImu + "," + kFoot0 + "," + kPose + ",gt_valid\n";
  const std::string pose = "1,2,3,1,0,0,0";
  std::istringstream in(header + "0,0,0,0,0,0,9.81," + kFoot0Row + "," + pose + ",1\n" +
                        "0.01,0,0,0,0,0,9.81," + kFoot0Row + ",0,0,0,0,0,0,0,0\n" +
                        "0.02,0,0,0,0,0,9.81," + kFoot0Row + "," + pose + ",1\n");
  const io::Log log = io::readLog(in, "real.csv");
  CHECK(log.layout.ground_truth);
  CHECK_FALSE(log.layout.gt_velocity);
  CHECK(log.layout.gt_valid);
  REQUIRE(log.rows.size() == 3);
  CHECK(log.rows[0].gt_valid);
  CHECK_FALSE(log.rows[1].gt_valid);
  CHECK(log.rows[1].gt_q.coeffs().isZero());  // a dropout row keeps what it held
  CHECK(log.rows[2].gt_p == Eigen::Vector3d(1, 2, 3));
  // Written back: no gt_v columns, the flag kept.
  const std::string again = write(log);
  CHECK(again.find("gt_vx") == std::string::npos);
  CHECK(again.find(",gt_valid\n") != std::string::npos);

  // The same zero quaternion on a valid row is refused.
  checkError(header + "0,0,0,0,0,0,9.81," + kFoot0Row + ",0,0,0,0,0,0,0,1\n", 2, "gt_qw",
             "expected a unit quaternion");
  checkError(header + "0,0,0,0,0,0,9.81," + kFoot0Row + "," + pose + ",1\n" +
                 "0.01,0,0,0,0,0,9.81," + kFoot0Row + "," + pose + ",0.5\n",
             3, "gt_valid", "expected a validity flag 0 (the truth is missing on this row) or 1");
  checkError(kImu + "," + kFoot0 + ",gt_valid\n", 1, "gt_valid",
             "a validity flag needs the ground-truth columns");
  checkError(kImu + "," + kFoot0 + "," + kPose + ",gt_vx,gt_vy\n", 1, "gt_vz",
             "needs all of gt_vx, gt_vy, gt_vz, or none of them");
  checkError(kImu + "," + kFoot0 + ",gt_px,gt_py,gt_pz,gt_qw,gt_qx,gt_qy\n", 1, "gt_qz",
             "needs all of gt_px..gt_qz (gt_vx..gt_vz and gt_valid are optional)");
}

TEST_CASE("Generic joint columns", "[57.0][log]") {
  std::istringstream in(kImu +
                        ",joint1_dq,joint0_q,joint1_q,joint0_dq,foot1_contact,foot0_contact\n" +
                        kImuRow + ",-2,0.5,0.25,4,1,0\n");
  const io::Log log = io::readLog(in, "real.csv");
  CHECK(log.layout.num_joints == 2);
  CHECK_FALSE(log.layout.joints);
  CHECK(log.layout.foot_columns == io::FootCovariance::kNone);
  CHECK(log.layout.num_feet == 2);
  CHECK(log.rows[0].joint_q.head<2>() == Eigen::Vector2d(0.5, 0.25));
  CHECK(log.rows[0].joint_dq.head<2>() == Eigen::Vector2d(4, -2));
  CHECK(log.rows[0].joint_q.tail<22>().isZero());
  CHECK(log.rows[0].contact[1]);

  // All 24 joints read; the 25th is out of range.
  std::string header = kImu;
  for (int k = 0; k < io::kMaxJoints; ++k) {
    header += ",joint" + std::to_string(k) + "_q,joint" + std::to_string(k) + "_dq";
  }
  std::string values = kImuRow;
  for (int k = 0; k < 2 * io::kMaxJoints; ++k) values += ",0.5";
  std::istringstream full(header + "\n" + values + "\n");
  CHECK(io::readLog(full, "real.csv").layout.num_joints == io::kMaxJoints);
  checkError(header + ",joint24_q,joint24_dq\n", 1, "joint24_q",
             "generic joint index out of range: at most 24 joints, joint0_ .. joint23_");
  checkError(kImu + ",joint0_q,joint0_dq,joint2_q,joint2_dq\n", 1, "joint1_q",
             "generic joints are numbered 0 .. 2 without a gap (joint2_ is there, joint1_ is "
             "not)");
  checkError(kImu + ",joint0_q,joint0_dq,joint1_q\n", 1, "joint1_dq",
             "each generic joint needs both joint<k>_q and joint<k>_dq");
  checkError(kImu + ",joint0_dq\n", 1, "joint0_q", "needs both joint<k>_q and joint<k>_dq");
  // Exclusive with the other two leg descriptions.
  std::string quadruped = kImu;
  for (const char* leg : io::kLegNames) {
    for (int j = 0; j < 3; ++j) {
      quadruped += std::string(",q_") + leg + "_" + std::to_string(j) + ",dq_" + leg + "_" +
                   std::to_string(j);
    }
  }
  checkError(quadruped + ",joint0_q,joint0_dq\n", 1, "",
             "the log describes its legs twice: generic joint columns (joint<k>_q, joint<k>_dq) "
             "and quadruped joint columns");
  checkError(kImu + "," + kFoot0 + ",joint0_q,joint0_dq\n", 1, "",
             "generic joint columns (joint<k>_q, joint<k>_dq) and body-frame foot columns");
  // Foot velocities belong to foot columns, not to generic joints.
  checkError(kImu + ",joint0_q,joint0_dq,foot0_vx,foot0_vy,foot0_vz\n", 1, "foot0_px",
             "need the foot position columns");
}

TEST_CASE("The writer refuses layouts the reader would", "[57.0][log]") {
  io::Log log;
  log.rows.resize(1);
  const auto refused = [&](const std::string& what) {
    std::ostringstream out;
    CHECK_THROWS_WITH(io::writeLog(out, log, "out.csv"), Catch::Matchers::Contains(what));
  };
  log.layout.num_joints = 3;  // with the quadruped's joints
  refused("generic joint columns (num_joints > 0) exclude the quadruped joint columns");
  log.layout.joints = false;
  log.layout.num_joints = io::kMaxJoints + 1;
  refused("num_joints = 25 (0 .. 24)");
  log.layout = io::LogLayout{};
  log.layout.foot_velocity = true;
  refused("foot velocity columns need foot columns");
  log.layout = io::LogLayout{};
  log.layout.gt_valid = true;
  refused("a gt_valid column needs the ground-truth columns");
  log.layout = io::LogLayout{};
  log.layout.gt_velocity = false;
  refused("gt_velocity = false describes a ground truth");
}
