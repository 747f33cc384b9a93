// Test helpers for programs that write files: a fresh scratch folder removed afterwards, a
// file's whole text, and a program run inside a folder with its output read back.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "spawn.hpp"

namespace legkit::test {

// <temp>/legkit_<name>_<pid>, empty at construction, removed with its contents at destruction
// (the pid keeps test programs that run at once apart).
struct ScratchFolder {
  std::filesystem::path path;
  explicit ScratchFolder(const std::string& name)
      : path(std::filesystem::temp_directory_path() /
             ("legkit_" + name + "_" + std::to_string(getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~ScratchFolder() { std::filesystem::remove_all(path); }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
};

// The whole text of a file ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream f(path);
  std::stringstream text;
  text << f.rdbuf();
  return text.str();
}

// A program's exit status (-1 if it did not exit) and its standard output and error together.
struct ProgramResult {
  int status = -1;
  std::string output;
};

// Runs argv inside `dir` (no shell: each argument reaches the program as it is), its output into
// dir/cli-output.txt, and reads that back.
inline ProgramResult runProgram(const std::filesystem::path& dir,
                                const std::vector<std::string>& argv) {
  const std::filesystem::path output = dir / "cli-output.txt";
  ProgramResult r;
  r.status = spawnAndWait(argv, dir.string(), output.string());
  r.output = slurp(output);
  return r;
}

}  // namespace legkit::test
