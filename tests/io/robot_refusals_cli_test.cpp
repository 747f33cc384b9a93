// Issue 23 items 3 and 4, nothing silently wrong: `legkit config --check` refuses what `legkit run`
// refuses (robot models the run cannot build, a directory, a second YAML document, zero noise
// densities), and robots that loaded wrong before are refused (a NaN in a URDF origin, feet on
// one leg, a NUL in a name, robot keys without a model, a log whose joint or foot count is not
// the robot's). Each refusal is exit 2 with a message naming the file and the key.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "legkit_cli.hpp"

namespace fs = std::filesystem;

namespace {

using Catch::Matchers::Contains;
using Result = legkit::test::ProgramResult;

using legkit::test::runLegkit;
using legkit::test::writeFile;

// A two-hinge leg: base -> thigh (hip) -> calf (knee) -> foot (fixed); `hip_origin` is the hip
// joint's origin xyz, `extra` goes before </robot>.
std::string legUrdf(const std::string& hip_origin = "0.1 0 0", const std::string& extra = "") {
  const std::string limit = R"(<limit lower="-1" upper="1" effort="1" velocity="1"/>)";
  return "<robot name=\"leg\">\n"
         "  <link name=\"base\"/>\n"
         "  <link name=\"thigh\"/>\n"
         "  <link name=\"calf\"/>\n"
         "  <link name=\"foot\"/>\n"
         "  <joint name=\"hip\" type=\"revolute\"><parent link=\"base\"/><child link=\"thigh\"/>"
         "<origin xyz=\"" +
         hip_origin + "\"/><axis xyz=\"0 1 0\"/>" + limit +
         "</joint>\n"
         "  <joint name=\"knee\" type=\"revolute\"><parent link=\"thigh\"/><child link=\"calf\"/>"
         "<origin xyz=\"0 0 -0.2\"/><axis xyz=\"0 1 0\"/>" +
         limit +
         "</joint>\n"
         "  <joint name=\"ankle\" type=\"fixed\"><parent link=\"calf\"/><child link=\"foot\"/>"
         "<origin xyz=\"0 0 -0.2\"/></joint>\n" +
         extra + "</robot>\n";
}

std::string robotYaml(const std::string& model, const std::string& base = "base",
                      const std::string& feet = "[foot]") {
  return "robot:\n  model: " + model + "\n  base: " + base + "\n  feet: " + feet + "\n";
}

// A generic-joints log of `joints` joint<k>_q/_dq columns and `feet` foot<k>_contact columns,
// still and level.
std::string genericLog(int joints, int feet) {
  std::string text = "t,gyro_x,gyro_y,gyro_z,acc_x,acc_y,acc_z";
  for (int k = 0; k < joints; ++k) {
    text += ",joint" + std::to_string(k) + "_q,joint" + std::to_string(k) + "_dq";
  }
  for (int k = 0; k < feet; ++k) text += ",foot" + std::to_string(k) + "_contact";
  text += "\n";
  for (int i = 0; i < 50; ++i) {
    text += std::to_string(0.01 * i) + ",0,0,0,0,0,9.81";
    for (int k = 0; k < 2 * joints; ++k) text += ",0";
    for (int k = 0; k < feet; ++k) text += ",1";
    text += "\n";
  }
  return text;
}

// `legkit config --check r.yaml` on `yaml`: exit 2 naming r.yaml, robot.model and `what`;
// `legkit run` on leg.csv (a log of the leg's joints) says the same.
void checkModelRefused(const fs::path& dir, const std::string& yaml, const std::string& what) {
  INFO(yaml);
  writeFile(dir / "r.yaml", yaml);
  Result r = runLegkit(dir, {"config", "--check", "r.yaml"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("r.yaml: robot.model: ") && Contains(what));
  r = runLegkit(dir, {"run", "--log", "leg.csv", "--config", "r.yaml", "--no-plots"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("r.yaml: robot.model: ") && Contains(what));
}

}  // namespace

TEST_CASE("config --check refuses the robot models legkit run refuses", "[cli][settings]") {
  const legkit::test::ScratchFolder dir("robot_refusals_model");
  writeFile(dir.path / "leg.csv", genericLog(2, 1));
  writeFile(dir.path / "leg.urdf", legUrdf());
  writeFile(dir.path / "r.yaml", robotYaml("leg.urdf"));
  Result r = runLegkit(dir.path, {"config", "--check", "r.yaml"});
  CHECK(r.status == 0);
  CHECK(r.output == "ok\n");

  checkModelRefused(dir.path, robotYaml("missing.urdf"), "cannot open the file");
  writeFile(dir.path / "cut.urdf", "<robot name=\"r\"><link name=\"base\"");
  checkModelRefused(dir.path, robotYaml("cut.urdf"), "MuJoCo cannot load it: XML parse error");
  writeFile(dir.path / "empty.urdf", "");
  checkModelRefused(dir.path, robotYaml("empty.urdf"),
                    "is empty: a robot model is a URDF or MJCF file");
  writeFile(dir.path / "binary.urdf", std::string("\x7f"
                                                  "ELF\x02\x01\x01\0\0\xff\xfe",
                                                  12));
  checkModelRefused(dir.path, robotYaml("binary.urdf"), "is not XML");
  checkModelRefused(dir.path, robotYaml("leg.urdf", "trunk"), "no body named 'trunk' for the base");
  checkModelRefused(dir.path, robotYaml("leg.urdf", "base", "[toe]"),
                    "no site or body named 'toe' for a foot");
  checkModelRefused(dir.path, robotYaml("leg.urdf", "base", "[base]"),
                    "foot 'base' (on body 'base') is not below the base");
  checkModelRefused(dir.path, robotYaml("leg.urdf", "base", "[a, b, c, d, e, f, g]"),
                    "7 feet named, the kit handles at most 6");

  std::string free = legUrdf();
  free.replace(free.find("revolute"), 8, "floating");
  writeFile(dir.path / "free.urdf", free);
  checkModelRefused(dir.path, robotYaml("free.urdf"), "free joint can only be used on top level");
  writeFile(dir.path / "loop.urdf",
            legUrdf("0.1 0 0",
                    "  <joint name=\"loop\" type=\"revolute\"><parent link=\"base\"/>"
                    "<child link=\"calf\"/><axis xyz=\"0 1 0\"/></joint>\n"));
  checkModelRefused(dir.path, robotYaml("loop.urdf"), "URDF body has multiple parents");

  std::string chain = "<robot name=\"chain\">\n  <link name=\"base\"/>\n";
  for (int k = 1; k <= 32; ++k) {
    const std::string parent = k == 1 ? "base" : "l" + std::to_string(k - 1);
    chain += "  <link name=\"l" + std::to_string(k) + "\"/><joint name=\"j" + std::to_string(k) +
             "\" type=\"continuous\"><parent link=\"" + parent + "\"/><child link=\"l" +
             std::to_string(k) + "\"/><axis xyz=\"0 1 0\"/></joint>\n";
  }
  writeFile(dir.path / "chain.urdf", chain + "</robot>\n");
  checkModelRefused(dir.path, robotYaml("chain.urdf", "base", "[l32]"),
                    "32 hinge and slide joints below the base 'base', the kit handles at most");

  writeFile(dir.path / "part.xml", "<mujoco/>\n");
  writeFile(dir.path / "include.xml",
            "<mujoco><include file=\"part.xml\"/><worldbody><body name=\"base\"><body name=\"b\">"
            "<joint name=\"h\"/><geom size=\".1\"/><site name=\"foot\"/></body></body></worldbody>"
            "</mujoco>\n");
  checkModelRefused(dir.path, robotYaml("include.xml"), "Empty include file 'part.xml'");
  // An external entity (XXE): never read, and its declaration refused (MuJoCo expands no entity:
  // "&x;" would stay as it is, in a name as much as in a number).
  std::string xxe = legUrdf();
  xxe.replace(xxe.find("<link name=\"thigh\"/>"), 20,
              "<link name=\"thigh\"><inertial><mass value=\"&x;\"/></inertial></link>");
  writeFile(
      dir.path / "xxe.urdf",
      "<?xml version=\"1.0\"?>\n<!DOCTYPE robot [<!ENTITY x SYSTEM \"file:///etc/passwd\">]>\n" +
          xxe);
  checkModelRefused(dir.path, robotYaml("xxe.urdf"),
                    "line 2: <!ENTITY>: the kit reads a plain URDF, and expands no entity");
}

TEST_CASE("robots that loaded wrong are refused, naming the file and the joint or key",
          "[cli][settings]") {
  const legkit::test::ScratchFolder dir("robot_refusals_robot");
  writeFile(dir.path / "leg.csv", genericLog(2, 1));

  // A NaN in a joint origin: MuJoCo reads it as 0.
  writeFile(dir.path / "nan.urdf", legUrdf("nan 0 0"));
  checkModelRefused(dir.path, robotYaml("nan.urdf"),
                    "robot model 'nan.urdf': line 6, joint 'hip': <origin xyz=\"nan 0 0\">: "
                    "expected finite numbers");
  writeFile(dir.path / "word.urdf", legUrdf("0.1 zero 0"));
  checkModelRefused(dir.path, robotYaml("word.urdf"), "joint 'hip': <origin xyz=\"0.1 zero 0\">");

  // In an MJCF: MuJoCo warns about a "nan" (and writes MUJOCO_LOG.TXT here) and takes an "inf".
  const auto mjcf = [](const std::string& pos) {
    return "<mujoco><worldbody><body name=\"base\"><body name=\"thigh\" pos=\"" + pos +
           "\"><joint name=\"hip\"/><geom size=\".1\"/><site name=\"foot\"/></body></body>"
           "</worldbody></mujoco>\n";
  };
  writeFile(dir.path / "nan.xml", mjcf("nan 0 0"));
  checkModelRefused(dir.path, robotYaml("nan.xml"), "MuJoCo warns: XML contains a 'NaN'");
  CHECK_FALSE(fs::exists(dir.path / "MUJOCO_LOG.TXT"));
  writeFile(dir.path / "inf.xml", mjcf("0 inf 0"));
  checkModelRefused(dir.path, robotYaml("inf.xml"),
                    "body 'thigh': a number that is not finite (NaN or inf in the file)");

  // Feet on one leg: a foot below another, in either order.
  writeFile(dir.path / "leg.urdf", legUrdf());
  checkModelRefused(dir.path, robotYaml("leg.urdf", "base", "[foot, calf]"),
                    "feet 'foot' and 'calf' are on one leg");
  checkModelRefused(dir.path, robotYaml("leg.urdf", "base", "[thigh, foot]"),
                    "feet 'thigh' and 'foot' are on one leg");

  // A NUL in a foot name: "foot\0x" would be "foot" to MuJoCo.
  writeFile(dir.path / "nul.yaml", robotYaml("leg.urdf", "base", "[\"foot\\0x\"]"));
  Result r = runLegkit(dir.path, {"config", "--check", "nul.yaml"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output,
             Contains("nul.yaml:4: robot.feet[0]: expected text without control characters"));
  writeFile(dir.path / "tab.yaml", robotYaml("leg.urdf", "\"base\\t\""));
  r = runLegkit(dir.path, {"config", "--check", "tab.yaml"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("tab.yaml:3: robot.base: expected text without control"));

  // robot.base, robot.feet or robot.joints without robot.model: the built-in Go2 has its own.
  for (const std::string key : {"base: base", "feet: [foot]", "joints: [hip]"}) {
    writeFile(dir.path / "nomodel.yaml", "robot:\n  " + key + "\n");
    r = runLegkit(dir.path, {"config", "--check", "nomodel.yaml"});
    CHECK(r.status == 2);
    CHECK_THAT(r.output, Contains("nomodel.yaml:2: robot." + key.substr(0, key.find(':')) +
                                  ": given without robot.model"));
  }

  // A log whose joint or foot count is not the robot's.
  writeFile(dir.path / "r.yaml", robotYaml("leg.urdf"));
  writeFile(dir.path / "three.csv", genericLog(3, 1));
  r = runLegkit(dir.path, {"run", "--log", "three.csv", "--config", "r.yaml", "--no-plots"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output,
             Contains("r.yaml: robot.joints: 2 joints, three.csv has 3 (joint<k>_q columns)"));
  writeFile(dir.path / "twofeet.csv", genericLog(2, 2));
  r = runLegkit(dir.path, {"run", "--log", "twofeet.csv", "--config", "r.yaml", "--no-plots"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("r.yaml: robot.feet: 1 feet, twofeet.csv has 2"));
  r = runLegkit(dir.path, {"run", "--log", "three.csv", "--no-plots"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("the built-in Go2 (no --config) has 12 joints, three.csv has 3"));
  // The matching log runs.
  r = runLegkit(dir.path, {"run", "--log", "leg.csv", "--config", "r.yaml", "--no-plots"});
  CHECK(r.status == 0);
}

TEST_CASE("settings files refused instead of read as something else", "[cli][settings]") {
  const legkit::test::ScratchFolder dir("robot_refusals_settings");
  // A directory: no longer the defaults.
  fs::create_directories(dir.path / "settings.d");
  Result r = runLegkit(dir.path, {"config", "--check", "settings.d"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("settings.d: is a directory"));
  r = runLegkit(dir.path, {"run", "--scenario", "trot", "--duration", "1", "--no-plots", "--config",
                           "settings.d"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("settings.d: is a directory"));
  CHECK_FALSE(fs::exists(dir.path / "legkit-out"));

  // A second document after ---: refused at its line; a leading --- is one document.
  writeFile(dir.path / "two.yaml",
            "imu:\n  gyro_noise_density: 0.001\n---\nimu:\n  gyro_noise_density: 0.5\n");
  r = runLegkit(dir.path, {"config", "--check", "two.yaml"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("two.yaml:4: a second YAML document"));
  writeFile(dir.path / "one.yaml", "---\nimu:\n  gyro_noise_density: 0.001\n");
  r = runLegkit(dir.path, {"config", "--check", "one.yaml"});
  CHECK(r.status == 0);

  // Zero white-noise densities (the filters refuse them later, naming neither file nor key); a
  // zero bias random walk (a constant bias) stays allowed.
  for (const std::string key : {"gyro_noise_density", "accel_noise_density"}) {
    writeFile(dir.path / "zero.yaml", "imu:\n  " + key + ": 0\n");
    r = runLegkit(dir.path, {"config", "--check", "zero.yaml"});
    CHECK(r.status == 2);
    CHECK_THAT(r.output, Contains("zero.yaml:2: imu." + key + ": expected a number in (0, "));
  }
  writeFile(dir.path / "walk.yaml",
            "imu:\n  gyro_bias_random_walk: 0\n  accel_bias_random_walk: 0\n");
  r = runLegkit(dir.path, {"config", "--check", "walk.yaml"});
  CHECK(r.status == 0);
}
