// The output helpers of the legkit commands (tools/legkit/output.hpp): a write that fails is an
// error naming the file, a half-written file never carries the final name, external programs
// get their arguments without a shell, tables keep their columns apart, progress stays readable.
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "output.hpp"
#include "scratch_folder.hpp"

namespace fs = std::filesystem;
using namespace legkit::tools;

namespace {

using Folder = legkit::test::ScratchFolder;
using legkit::test::slurp;

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
  const Folder dir("output_atomic");
  const fs::path file = dir.path / "a.csv";
  writeAtomically(file, [](std::ostream& f) { f << "old\n"; });
  CHECK(slurp(file) == "old\n");
  CHECK_FALSE(fs::exists(dir.path / "a.csv.tmp"));

  // A .tmp that is a link (to a device) is neither followed nor removed: refused.
  fs::create_symlink("/dev/full", dir.path / "a.csv.tmp");
  CHECK_THROWS_WITH(writeAtomically(file, kMegabyte),
                    Catch::Matchers::StartsWith("cannot write " + file.string()) &&
                        Catch::Matchers::Contains("not a regular file"));
  CHECK(slurp(file) == "old\n");
  CHECK(fs::is_symlink(dir.path / "a.csv.tmp"));
  // A target that is a device, or a link to one, is never replaced (as root a rename would).
  const fs::path link = dir.path / "null-link";
  fs::create_symlink("/dev/null", link);
  CHECK_THROWS_WITH(writeAtomically(link, kMegabyte),
                    Catch::Matchers::Contains("not a regular file"));
  CHECK(fs::is_symlink(link));
  CHECK_THROWS_WITH(writeAtomically("/dev/null", kMegabyte),
                    Catch::Matchers::Contains("/dev/null exists and is not a regular file"));
  CHECK(fs::is_character_file("/dev/null"));
  CHECK_FALSE(fs::exists("/dev/null.tmp"));

  CHECK_THROWS_WITH(writeAtomically(dir.path / "no-such-folder" / "b.csv", kMegabyte),
                    Catch::Matchers::Contains("no-such-folder/b.csv"));
  // An output folder that is a regular file.
  CHECK_THROWS_WITH(makeOutputFolder(file), Catch::Matchers::Contains(file.string()));
}

TEST_CASE("output: a folder's previous run removes only what its manifest listed", "[cli]") {
  const Folder dir("output_folder");
  const fs::path out = dir.path / "out";
  {
    OutputFolder first(out, "summary.json");
    first.write("estimate_a.csv", [](std::ostream& f) { f << "a\n"; });
    first.write("estimate_b.csv", [](std::ostream& f) { f << "b\n"; });
    first.writeManifest({{"legkit_version", "test"}});
    CHECK(first.written() ==
          std::vector<std::string>{"estimate_a.csv", "estimate_b.csv", "summary.json"});
  }
  // The user's own files beside them, a .tmp a killed run left, and a manifest entry that climbs
  // out of the folder (written by hand: the kit never lists one).
  std::ofstream(out / "estimate_mine.csv") << "mine\n";
  std::ofstream(out / "figure.png") << "mine\n";
  // The user's figure is an hour old (a fresh one is within the file clock's slack of `drawing`).
  fs::last_write_time(out / "figure.png", fs::file_time_type::clock::now() - std::chrono::hours(1));
  std::ofstream(out / "estimate_a.csv.tmp") << "half\n";
  std::ofstream(dir.path / "outside.csv") << "mine\n";
  nlohmann::json manifest = nlohmann::json::parse(slurp(out / "summary.json"));
  manifest["outputs"].push_back("../outside.csv");
  std::ofstream(out / "summary.json") << manifest.dump();

  const fs::file_time_type drawing = fs::file_time_type::clock::now();
  OutputFolder second(out, "summary.json");
  for (const char* gone :
       {"estimate_a.csv", "estimate_b.csv", "estimate_a.csv.tmp", "summary.json"})
    CHECK_FALSE(fs::exists(out / gone));
  for (const fs::path& kept :
       {out / "estimate_mine.csv", out / "figure.png", dir.path / "outside.csv"})
    CHECK(slurp(kept) == "mine\n");
  // A figure drawn after the folder was opened is the run's; the user's older one is not.
  std::ofstream(out / "drawn.png") << "png\n";
  // Stamped by the kernel's coarse clock, a tick behind `drawing` (as it was once under ASan).
  fs::last_write_time(out / "drawn.png", drawing - std::chrono::milliseconds(4));
  second.adopt(".png", drawing);
  CHECK(second.written() == std::vector<std::string>{"drawn.png"});

  // A summary.json that is not a legkit run's: nothing removed.
  std::ofstream(out / "summary.json") << "{\"mine\": 1}\n";
  CHECK_THROWS_WITH(OutputFolder(out, "summary.json"),
                    Catch::Matchers::Contains("summary.json is not a legkit run's"));
  CHECK(fs::exists(out / "drawn.png"));
  CHECK(fs::exists(out / "summary.json"));
}

TEST_CASE("output: programs run without a shell; their errors are kept", "[cli]") {
  const Folder dir("output_spawn");
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
  // A failure is an output not written (the commands exit 2); plots left undrawn for want of
  // matplotlib are said, not failed.
  CHECK(plotFailed(message));
  CHECK_FALSE(plotFailed(""));
  CHECK_FALSE(plotFailed("plots not drawn: python3-matplotlib is not installed"));
}

TEST_CASE("output: a table's columns never run together", "[cli]") {
  std::ostringstream out;
  printTable(out, {{"parameter", "scale", "vel bias [m/s]", "vel variance [m2/s2]"},
                   {"accelerometer noise", "0.001", "0.0123", "0.000456"},
                   {"short", "1000.000"}});
  const std::string text = out.str();
  INFO(text);
  // The header that filled its old fixed width exactly is still apart from its neighbour.
  CHECK_THAT(text, Catch::Matchers::Contains("vel bias [m/s]  vel variance [m2/s2]\n"));
  // "parameter" padded to "accelerometer noise", two spaces, "scale" padded to "1000.000".
  CHECK_THAT(text,
             Catch::Matchers::StartsWith("parameter" + std::string(10 + 2 + 3, ' ') + "scale"));
  std::istringstream lines(text);
  std::vector<std::string> line(3);
  for (std::string& l : line) std::getline(lines, l);
  // Numbers right-aligned under their headers; the first column left-aligned; no trailing blanks.
  CHECK(line[1].size() == line[0].size());
  CHECK(line[0].find("scale") + 5 == line[1].find("0.001") + 5);
  CHECK(line[2] == "short                1000.000");
}

TEST_CASE("output: progress redrawn in place on a terminal, plain lines elsewhere", "[cli]") {
  std::ostringstream terminal;
  {
    Progress p(terminal, true);
    p.run("consistency", 9, 12);
    p.run("consistency", 10, 12);
    p.run("c", 1, 2);  // a shorter line blanks out the rest of the longer one
  }                    // the destructor wipes the line
  CHECK(terminal.str() == "\rconsistency: run 9/12\rconsistency: run 10/12\rc: run 1/2" +
                              std::string(12, ' ') + "\r" + std::string(10, ' ') + "\r");

  std::ostringstream file;
  Progress p(file, false);
  for (int done = 1; done <= 40; ++done) p.run("consistency", done, 40);
  p.clear();
  const std::string text = file.str();
  INFO(text);
  CHECK(text.find('\r') == std::string::npos);
  CHECK(std::count(text.begin(), text.end(), '\n') == 10);  // each tenth of 40 runs
  CHECK_THAT(text, Catch::Matchers::StartsWith("consistency: run 4/40\n"));
  CHECK_THAT(text, Catch::Matchers::EndsWith("consistency: run 40/40\n"));
  std::ostringstream few;
  Progress q(few, false);
  for (int done = 1; done <= 3; ++done) q.run("sweep", done, 3);
  CHECK(few.str() == "sweep: run 1/3\nsweep: run 2/3\nsweep: run 3/3\n");
}
