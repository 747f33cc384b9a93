// Starting a program without a shell (an argument vector, never a command string, so that no
// character of a path is ever read as shell syntax), and waiting for it. Used by the plotting in
// output.cpp and by the tests that run legkit.
#pragma once

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <string>
#include <vector>

extern char** environ;

namespace legkit::tools {

// Starts argv[0] (a path) with argv and the given file actions; 0, or the errno of the failure.
inline int spawnProgram(const std::vector<std::string>& argv,
                        const posix_spawn_file_actions_t& actions, pid_t& pid) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  return posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
}

// The exit status of pid once it ends, -1 if it did not exit normally.
inline int waitForExit(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace legkit::tools
