#include "output.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

extern char** environ;

namespace legkit::tools {

namespace fs = std::filesystem;

void writeAtomically(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw OutputError("cannot write " + path.string() + ": cannot create " + tmp.string());
    write(f);
    f.flush();
    f.close();
    if (f.fail()) {
      std::error_code ignored;
      fs::remove(tmp, ignored);
      throw OutputError("cannot write " + path.string() +
                        ": the write failed (is the disk full?)");
    }
  }
  std::error_code error;
  fs::rename(tmp, path, error);
  if (error) throw OutputError("cannot write " + path.string() + ": " + error.message());
}

void makeOutputFolder(const fs::path& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir)) {
    throw OutputError("cannot use " + dir.string() + " as the output folder" +
                      (error ? ": " + error.message() : ": it is not a folder"));
  }
}

ProgramResult runProgram(const std::vector<std::string>& argv) {
  ProgramResult result;
  std::array<int, 2> pipe_ends{};
  if (argv.empty() || pipe(pipe_ends.data()) != 0) return result;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, pipe_ends[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipe_ends[0]);
  posix_spawn_file_actions_addclose(&actions, pipe_ends[1]);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(pipe_ends[1]);
  if (spawned != 0) {
    close(pipe_ends[0]);
    result.errors = "cannot start " + argv[0] + ": " + std::strerror(spawned);
    return result;
  }
  std::array<char, 4096> chunk{};
  ssize_t n = 0;
  while ((n = read(pipe_ends[0], chunk.data(), chunk.size())) > 0 || (n < 0 && errno == EINTR)) {
    if (n > 0) result.errors.append(chunk.data(), static_cast<std::size_t>(n));
    if (result.errors.size() > 4000) result.errors.erase(0, result.errors.size() - 2000);
  }
  close(pipe_ends[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (result.errors.size() > 2000) result.errors.erase(0, result.errors.size() - 2000);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

std::string plot(const std::string& script, const std::vector<std::string>& arguments) {
  const std::string python = "/usr/bin/python3";
  if (!fs::exists(python)) return "plots not drawn: " + python + " is not installed";
  std::vector<std::string> argv = {python, LEGKIT_SOURCE_DIR "/tools/plots/" + script};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  const ProgramResult r = runProgram(argv);
  if (r.status == 0) return "";
  // The last non-empty line of the script's errors says what failed.
  std::string last;
  std::size_t end = r.errors.find_last_not_of("\n ");
  if (end != std::string::npos) {
    const std::size_t start = r.errors.rfind('\n', end);
    last = r.errors.substr(start == std::string::npos ? 0 : start + 1, end + 1 - (start + 1));
  }
  if (last.find("No module named 'matplotlib'") != std::string::npos) {
    return "plots not drawn: python3-matplotlib is not installed";
  }
  return "plots FAILED (" + script + "): " + (last.empty() ? "no message" : last);
}

}  // namespace legkit::tools
