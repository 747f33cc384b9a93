// The legkit program in a test: LEGKIT_EXE (each CLI test target's compile definition) run inside
// a scratch folder, and what a run leaves there.
#pragma once

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scratch_folder.hpp"

namespace legkit::test {

// `legkit ARGUMENTS` inside `dir`: its exit status and its output (stdout and stderr).
inline ProgramResult runLegkit(const std::filesystem::path& dir,
                               std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), LEGKIT_EXE);
  return runProgram(dir, arguments);
}

// The same, the output into `output`; returns the exit status.
inline int runLegkit(const std::filesystem::path& dir, std::vector<std::string> arguments,
                     std::string& output) {
  ProgramResult r = runLegkit(dir, std::move(arguments));
  output = std::move(r.output);
  return r.status;
}

// The summary.json of a run's output folder.
inline nlohmann::json readSummary(const std::filesystem::path& out) {
  std::ifstream in(out / "summary.json");
  return nlohmann::json::parse(in);
}

// Writes `text` to `path` as it is (binary: no newline translation).
inline void writeFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace legkit::test
