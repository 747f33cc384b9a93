// Runs a program for a test without a shell: an argument vector, a working folder, and standard
// output and error both sent to one file. Returns the exit status, -1 if it did not exit.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "tools/legkit/spawn.hpp"

namespace legkit::test {

inline int spawnAndWait(const std::vector<std::string>& argv, const std::string& dir,
                        const std::string& output) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, output.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int spawned = tools::spawnProgram(argv, actions, pid);
  posix_spawn_file_actions_destroy(&actions);
  return spawned == 0 ? tools::waitForExit(pid) : -1;
}

}  // namespace legkit::test
