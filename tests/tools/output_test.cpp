// The output helpers of the legkit commands (tools/legkit/output.hpp): a write that fails is an
// error naming the file, a half-written file never carries the final name, and external programs
// get their arguments without a shell.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "output.hpp"

namespace fs = std::filesystem;
using namespace legkit::tools;

namespace {

struct Folder {
  fs::path path;
  explicit Folder(const std::string& name)
      : path(fs::temp_directory_path() /
             ("legkit_output_" + name + "_" + std::to_string(getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Folder() { fs::remove_all(path); }
};

std::string slurp(const fs::path& path) {
  std::ifstream f(path);
  std::stringstream text;
  text << f.rdbuf();
  return text.str();
}

const auto kMegabyte = [](std::ostream& f) { f << std::string(1 << 20, 'x'); };

}  // namespace

TEST_CASE("output: a write to a full disk is an error that names the file", "[cli]") {
  try {
    writeChecked("/dev/full", kMegabyte, "estimate_eskf.csv");
    FAIL("no error for /dev/full");
  } catch (const OutputError& e) {
    CHECK_THAT(e.what(), Catch::Matchers::StartsWith("cannot write estimate_eskf.csv"));
    CHECK_THAT(e.what(), Catch::Matchers::Contains("disk full"));
  }
  // A few bytes sit in the stream's buffer until the flush: still caught.
  CHECK_THROWS_AS(writeChecked("/dev/full", [](std::ostream& f) { f << "1\n"; }), OutputError);
}

TEST_CASE("output: writeAtomically keeps the old file when the new one cannot be written",
          "[cli]") {
  const Folder dir("atomic");
  const fs::path file = dir.path / "a.csv";
  writeAtomically(file, [](std::ostream& f) { f << "old\n"; });
  CHECK(slurp(file) == "old\n");
  CHECK_FALSE(fs::exists(dir.path / "a.csv.tmp"));

  fs::create_symlink("/dev/full", dir.path / "a.csv.tmp");
  CHECK_THROWS_WITH(writeAtomically(file, kMegabyte),
                    Catch::Matchers::StartsWith("cannot write " + file.string()));
  CHECK(slurp(file) == "old\n");
  CHECK_FALSE(fs::is_symlink(dir.path / "a.csv.tmp"));

  CHECK_THROWS_WITH(writeAtomically(dir.path / "no-such-folder" / "b.csv", kMegabyte),
                    Catch::Matchers::Contains("no-such-folder/b.csv"));
  // An output folder that is a regular file.
  CHECK_THROWS_WITH(makeOutputFolder(file), Catch::Matchers::Contains(file.string()));
}

TEST_CASE("output: programs run without a shell; their errors are kept", "[cli]") {
  const Folder dir("spawn");
  const fs::path odd = dir.path / "x'; touch INJECTED; echo '";
  const ProgramResult touched = runProgram({"/usr/bin/touch", odd.string()});
  CHECK(touched.status == 0);
  CHECK(fs::exists(odd));  // one file with that name: no shell split it
  CHECK_FALSE(fs::exists("INJECTED"));
  CHECK_FALSE(fs::exists(dir.path / "INJECTED"));

  const ProgramResult failed =
      runProgram({"/bin/sh", "-c", "echo first >&2; echo last >&2; exit 4"});
  CHECK(failed.status == 4);
  CHECK(failed.errors == "first\nlast\n");

  const ProgramResult missing = runProgram({(dir.path / "no-such-program").string()});
  CHECK(missing.status != 0);
}

TEST_CASE("output: a failing plot script is reported with what it said", "[cli]") {
  const std::string message = plot("no-such-script.py", {});
  CHECK_THAT(message, Catch::Matchers::StartsWith("plots FAILED: no-such-script.py exited"));
  CHECK_THAT(message, Catch::Matchers::Contains("No such file"));
  CHECK_THAT(message, !Catch::Matchers::Contains("matplotlib"));
}
