// What the legkit commands share about their output: the exit codes, the errors that map onto
// them, files written so that a half-written one never carries the final name, and external
// programs (the plot scripts) started without a shell.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace legkit::tools {

// Exit codes of every legkit command (README, `legkit --help`).
enum ExitCode : int {
  kExitOk = 0,         // done; every estimator finished healthy
  kExitUsage = 1,      // the command line was wrong
  kExitInput = 2,      // the input could not be used or the output not written: nothing reported
  kExitUnhealthy = 3,  // the run finished, but an estimator failed or had to recover
};

// The command line asks for something that does not exist (an unknown leg, a malformed
// --dropout): exit code 1, like CLI11's own parse errors.
class UsageError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};
// The input cannot be used (a time base that is not in seconds, a gap): exit code 2.
class InputError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};
// An output could not be written: exit code 2.
class OutputError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Writes `path` itself through `write`, then checks the stream after flushing and closing it.
// Throws OutputError("cannot write <name>: ...") on any failure (name defaults to path): a file
// that cannot be created, a full disk (/dev/full).
void writeChecked(const std::filesystem::path& path,
                  const std::function<void(std::ostream&)>& write, const std::string& name = "");

// Writes path through `write` into "<path>.tmp", checks the stream after flushing and closing it,
// and only then renames it to path. Throws OutputError naming path (or `name`, e.g. "x.csv
// (--out)") on any failure (a full disk, a missing folder); path then keeps whatever it held
// before. Only regular files are replaced: a path (or its .tmp) that is a device, a link, a folder
// or a FIFO is an OutputError, untouched.
void writeAtomically(const std::filesystem::path& path,
                     const std::function<void(std::ostream&)>& write, const std::string& name = "");

// Throws OutputError naming path (or `name`) unless writeAtomically could replace it: path and
// its .tmp absent or regular files, in a folder that exists. For a check before a long run, so
// that the run is not spent for an output it cannot write (legkit-estimate --out).
void checkWritable(const std::filesystem::path& path, const std::string& name = "");

// Creates the folder (and its parents) for a command's outputs, or throws OutputError.
void makeOutputFolder(const std::filesystem::path& dir);

// A command's output folder, which may hold a previous run's outputs and the user's own files.
// The run's manifest (a JSON file whose "outputs" lists the names of the files the run wrote,
// written last) is what tells the two apart: opening the folder removes the previous manifest
// first (the folder is incomplete from then on), then exactly the files it listed and the .tmp
// files a killed run left of them, and nothing else. A manifest that is not a JSON object with
// "legkit_version" is not the kit's: OutputError, nothing removed.
class OutputFolder {
 public:
  OutputFolder(std::filesystem::path dir, std::string manifest);
  std::filesystem::path path(const std::string& name) const { return dir_ / name; }
  // writeAtomically(path(name), write), and `name` recorded as written.
  void write(const std::string& name, const std::function<void(std::ostream&)>& write);
  // Records the regular files matching `extension` modified since `since` (a script's figures).
  // File times come from the kernel's coarse clock, up to a scheduler tick (10 ms at HZ=100)
  // behind `clock::now()`: a file written right after `since` was taken can carry an earlier
  // time, so the comparison allows 50 ms (seen under ASan: a figure written just after `since`
  // was stamped before it).
  void adopt(const std::string& extension, std::filesystem::file_time_type since);
  // The names written so far, for the manifest.
  const std::vector<std::string>& written() const { return written_; }
  // Writes the manifest: `summary` with "outputs" set to written() and the manifest itself.
  void writeManifest(nlohmann::json summary);

 private:
  std::filesystem::path dir_;
  std::string manifest_;
  std::vector<std::string> written_;
};

// A text table: each column as wide as its widest cell, columns two spaces apart, the first
// left-aligned and the others right-aligned (numbers). Rows may have fewer cells than others.
void printTable(std::ostream& out, const std::vector<std::vector<std::string>>& rows);

// value in %.<digits>g, "-" for NaN (a table's cell).
std::string formatG(double value, int digits);
// value with `precision` digits after the point, "-" for NaN (a table's cell).
std::string formatFixed(double value, int precision);

// A study's progress on standard error, never in its results: "consistency: run 3/12", redrawn in
// place when it goes to a terminal (in_place), else as plain lines, at most about ten per batch
// of runs (each tenth and the last) so that a log file stays readable.
class Progress {
 public:
  Progress(std::ostream& err, bool in_place) : err_(err), in_place_(in_place) {}
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  ~Progress() { clear(); }  // also when a run fails: its message then starts on a clean line
  // "<what>: run done/total"
  void run(const std::string& what, int done, int total);
  // Wipes the line drawn in place (nothing for plain lines), before the results are printed.
  void clear();

 private:
  std::ostream& err_;
  bool in_place_;
  std::size_t drawn_ = 0;  // length of the line drawn in place
};

// Runs argv[0] with the arguments argv[1..] directly (posix_spawn, no shell: nothing in an
// argument is ever interpreted), its standard output discarded.
struct ProgramResult {
  int status = -1;     // exit status, -1 if it could not be started or was killed
  std::string errors;  // the last 2000 characters of its standard error
};
ProgramResult runProgram(const std::vector<std::string>& argv);

// Whether plot()'s answer is a failure (the script ran and failed: exit code 2, an output not
// written), not plots left undrawn because python3 or matplotlib is missing (said, exit 0).
inline bool plotFailed(const std::string& answer) {
  return answer.rfind("plots FAILED", 0) == 0;
}

// Draws a command's figures with one of the kit's plot scripts (tools/plots/<script>) and says in
// one line what came of it: empty when the figures were drawn, else what went wrong (the last
// lines of the script's errors; python3 or matplotlib blamed only when really missing).
std::string plot(const std::string& script, const std::vector<std::string>& arguments);

}  // namespace legkit::tools
