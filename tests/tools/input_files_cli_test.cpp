// Issue 23 item 10: a directory, a device or a FIFO given where the kit reads a file (a log, an
// allan input, the manager's log, a settings file, a robot model) is refused with a message
// naming the path, before it is opened (a directory used to fail on its first read with
// "basic_filebuf::underflow ... Is a directory" and no path; a FIFO blocked in open(); /dev/zero
// as a settings file or a robot model allocated until the memory ran out). A settings file or a
// robot model larger than 16 MiB is refused naming the file and the cap.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scratch_folder.hpp"
#include "spawn.hpp"

namespace fs = std::filesystem;

namespace {

using Catch::Matchers::Contains;
using Result = legkit::test::ProgramResult;

Result run(const fs::path& dir, const char* exe, std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), exe);
  return legkit::test::runProgram(dir, arguments);
}

Result runLegkit(const fs::path& dir, std::vector<std::string> arguments) {
  return run(dir, LEGKIT_EXE, std::move(arguments));
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// Refused (a nonzero exit) with `path: what`, and not with the stream library's words.
void checkRefused(const Result& r, const std::string& path, const std::string& what) {
  INFO(r.output);
  CHECK(r.status != 0);
  CHECK(r.status != -1);
  CHECK_THAT(r.output, Contains(path + ": " + what));
  CHECK_THAT(r.output, !Contains("basic_filebuf") && !Contains("bad_alloc"));
}

}  // namespace

TEST_CASE("a directory as a log, an allan input, a manager log or a settings file is refused",
          "[cli][issue23]") {
  const legkit::test::ScratchFolder dir("input_files_directory");
  fs::create_directories(dir.path / "logs");
  checkRefused(runLegkit(dir.path, {"run", "--log", "logs", "--no-plots"}), "logs",
               "is a directory");
  checkRefused(runLegkit(dir.path, {"allan", "logs"}), "logs", "is a directory");
  checkRefused(run(dir.path, LEGKIT_ESTIMATE_EXE, {"logs"}), "logs", "is a directory");
  checkRefused(runLegkit(dir.path, {"config", "--check", "logs"}), "logs", "is a directory");
}

TEST_CASE("/dev/zero as a log, an allan input, a settings file or a robot model is refused",
          "[cli][issue23]") {
  const legkit::test::ScratchFolder dir("input_files_device");
  checkRefused(runLegkit(dir.path, {"run", "--log", "/dev/zero", "--no-plots"}), "/dev/zero",
               "is a device, not a regular file");
  checkRefused(runLegkit(dir.path, {"allan", "/dev/zero"}), "/dev/zero",
               "is a device, not a regular file");
  checkRefused(runLegkit(dir.path, {"config", "--check", "/dev/zero"}), "/dev/zero",
               "is a device, not a regular file");
  write(dir.path / "r.yaml", "robot:\n  model: /dev/zero\n  base: base\n  feet: [foot]\n");
  const Result r = runLegkit(dir.path, {"config", "--check", "r.yaml"});
  checkRefused(r, "robot model '/dev/zero'", "is not a regular file");
  CHECK_THAT(r.output, Contains("r.yaml: robot.model: "));
}

TEST_CASE("a FIFO as a log or a settings file is refused, not waited on", "[cli][issue23]") {
  const legkit::test::ScratchFolder dir("input_files_fifo");
  REQUIRE(mkfifo((dir.path / "pipe").c_str(), 0600) == 0);
  checkRefused(runLegkit(dir.path, {"run", "--log", "pipe", "--no-plots"}), "pipe", "is a FIFO");
  checkRefused(runLegkit(dir.path, {"allan", "pipe"}), "pipe", "is a FIFO");
  checkRefused(runLegkit(dir.path, {"config", "--check", "pipe"}), "pipe", "is a FIFO");
}

TEST_CASE("a settings file or a robot model over 16 MiB is refused naming the cap",
          "[cli][issue23]") {
  const legkit::test::ScratchFolder dir("input_files_large");
  const std::string comment = "# " + std::string(1022, 'x') + "\n";  // 1 KiB
  {
    std::ofstream big(dir.path / "big.yaml", std::ios::binary);
    for (int k = 0; k < 17 * 1024; ++k) big << comment;
  }
  checkRefused(runLegkit(dir.path, {"config", "--check", "big.yaml"}), "big.yaml",
               "is larger than the 16 MiB (16777216 bytes) a settings file may be");
  {
    std::ofstream big(dir.path / "big.urdf", std::ios::binary);
    big << "<robot name=\"r\">\n";
    const std::string spaces(1024, ' ');
    for (int k = 0; k < 17 * 1024; ++k) big << spaces;
    big << "</robot>\n";
  }
  write(dir.path / "r.yaml", "robot:\n  model: big.urdf\n  base: base\n  feet: [foot]\n");
  const Result r = runLegkit(dir.path, {"config", "--check", "r.yaml"});
  checkRefused(r, "big.urdf'", "is larger than the 16 MiB (16777216 bytes) a robot model may be");
  CHECK_THAT(r.output, Contains("r.yaml: robot.model: "));
}
