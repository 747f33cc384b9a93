#include "output.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include "spawn.hpp"

namespace legkit::tools {

namespace fs = std::filesystem;

void writeChecked(const fs::path& path, const std::function<void(std::ostream&)>& write,
                  const std::string& name) {
  const std::string shown = name.empty() ? path.string() : name;
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) {
    throw OutputError("cannot write " + shown + ": cannot create " + path.string() + ": " +
                      std::strerror(errno));
  }
  write(f);
  f.flush();
  const bool written = static_cast<bool>(f);
  f.close();
  if (!written || f.fail()) {
    throw OutputError("cannot write " + shown + ": the write failed (is the disk full?)");
  }
}

namespace {

// Throws OutputError unless `path` is absent or a regular file (never a link: it is not followed).
void checkReplaceable(const fs::path& path, const std::string& shown) {
  std::error_code error;
  const fs::file_status status = fs::symlink_status(path, error);
  if (error || status.type() == fs::file_type::not_found || fs::is_regular_file(status)) return;
  throw OutputError("cannot write " + shown + ": " + path.string() +
                    " exists and is not a regular file (a device, a link, a folder or a FIFO): "
                    "the kit replaces only regular files");
}

// The .tmp files being written, removed by a SIGTERM, SIGINT or SIGHUP before the program dies of
// it: a killed run leaves no .tmp behind (OutputFolder removes those of a previous run's listed
// outputs only, and a run killed before its manifest lists none). A fixed table of slots, so that
// the handler touches nothing but lock-free atomics, char arrays and unlink() (async-signal-safe);
// a path too long for a slot is just not removed.
struct TmpSlot {
  std::atomic<int> state{0};  // 0 free, 1 being filled, 2 a .tmp being written
  char path[4096] = {};
};
TmpSlot g_tmp_slots[16];

extern "C" void removeTmpFilesAndDie(int signal_number) {
  for (TmpSlot& slot : g_tmp_slots) {
    if (slot.state.load() == 2) ::unlink(slot.path);
  }
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);  // the exit status still says which signal ended the program
}

// Registers `tmp` in a free slot for the handler while it lives.
class TmpFileGuard {
 public:
  explicit TmpFileGuard(const std::string& tmp) {
    static const bool installed = [] {
      for (const int s : {SIGTERM, SIGINT, SIGHUP}) std::signal(s, removeTmpFilesAndDie);
      return true;
    }();
    (void)installed;
    if (tmp.size() >= sizeof(TmpSlot::path)) return;
    for (TmpSlot& slot : g_tmp_slots) {
      int expected = 0;
      if (!slot.state.compare_exchange_strong(expected, 1)) continue;
      std::memcpy(slot.path, tmp.c_str(), tmp.size() + 1);
      slot.state.store(2);
      slot_ = &slot;
      return;
    }
  }
  ~TmpFileGuard() {
    if (slot_) slot_->state.store(0);
  }
  TmpFileGuard(const TmpFileGuard&) = delete;
  TmpFileGuard& operator=(const TmpFileGuard&) = delete;

 private:
  TmpSlot* slot_ = nullptr;
};

}  // namespace

void checkWritable(const fs::path& path, const std::string& name) {
  const std::string shown = name.empty() ? path.string() : name;
  checkReplaceable(path, shown);
  checkReplaceable(path.string() + ".tmp", shown);
  const fs::path folder = path.parent_path();
  std::error_code ignored;
  if (!folder.empty() && !fs::is_directory(folder, ignored)) {
    throw OutputError("cannot write " + shown + ": " + folder.string() + " is not a folder");
  }
}

void writeAtomically(const fs::path& path, const std::function<void(std::ostream&)>& write,
                     const std::string& name) {
  const std::string shown = name.empty() ? path.string() : name;
  const fs::path tmp = path.string() + ".tmp";
  checkReplaceable(path, shown);
  checkReplaceable(tmp, shown);
  const TmpFileGuard guard(tmp.string());
  try {
    writeChecked(tmp, write, shown);
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
  std::error_code error;
  fs::rename(tmp, path, error);
  if (error) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw OutputError("cannot write " + shown + ": " + error.message());
  }
}

void makeOutputFolder(const fs::path& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir)) {
    throw OutputError("cannot use " + dir.string() + " as the output folder" +
                      (error ? ": " + error.message() : ": it is not a folder"));
  }
}

OutputFolder::OutputFolder(fs::path dir, std::string manifest)
    : dir_(std::move(dir)), manifest_(std::move(manifest)) {
  makeOutputFolder(dir_);
  const fs::path previous = dir_ / manifest_;
  std::error_code error;
  if (!fs::exists(fs::symlink_status(previous, error))) return;
  nlohmann::json listed;
  {
    std::ifstream in(previous);
    listed = nlohmann::json::parse(in, nullptr, false);
  }
  if (!listed.is_object() || !listed.contains("legkit_version")) {
    throw OutputError("cannot use " + dir_.string() + " as the output folder: its " + manifest_ +
                      " is not a legkit run's (nothing removed; choose another folder)");
  }
  const auto remove = [](const fs::path& p) {
    std::error_code e;
    if (!fs::is_regular_file(fs::symlink_status(p, e))) return;  // only the kit's regular files
    fs::remove(p, e);
    if (e) throw OutputError("cannot remove the stale " + p.string() + ": " + e.message());
  };
  remove(previous);
  const nlohmann::json outputs = listed.value("outputs", nlohmann::json::array());
  if (!outputs.is_array()) return;
  for (const nlohmann::json& name : outputs) {
    // A plain file name of this folder: nothing with a separator, nothing that climbs out.
    if (!name.is_string()) continue;
    const std::string n = name.get<std::string>();
    if (n.empty() || n == "." || n == ".." || n.find('/') != std::string::npos) continue;
    remove(dir_ / n);
    remove(dir_ / (n + ".tmp"));
  }
  remove(dir_ / (manifest_ + ".tmp"));
}

void OutputFolder::write(const std::string& name, const std::function<void(std::ostream&)>& write) {
  writeAtomically(path(name), write);
  written_.push_back(name);
}

void OutputFolder::adopt(const std::string& extension, fs::file_time_type since) {
  constexpr std::chrono::milliseconds kFileClockSlack{50};  // > a tick at HZ=100, 250 or 1000
  since -= kFileClockSlack;
  std::vector<std::string> found;
  for (const fs::directory_entry& e : fs::directory_iterator(dir_)) {
    std::error_code error;
    if (e.path().extension() != extension || !e.is_regular_file(error)) continue;
    if (e.last_write_time(error) >= since && !error) found.push_back(e.path().filename().string());
  }
  std::sort(found.begin(), found.end());
  written_.insert(written_.end(), found.begin(), found.end());
}

void OutputFolder::writeManifest(nlohmann::json summary) {
  written_.push_back(manifest_);
  summary["outputs"] = written_;
  writeAtomically(path(manifest_), [&](std::ostream& f) { f << summary.dump(2) << '\n'; });
}

std::string formatFixed(double value, int precision) {
  if (std::isnan(value)) return "-";
  std::ostringstream os;
  os << std::fixed << std::setprecision(precision) << value;
  return os.str();
}

std::string formatG(double value, int digits) {
  if (std::isnan(value)) return "-";
  char text[32];
  std::snprintf(text, sizeof(text), "%.*g", digits, value);
  return text;
}

void printTable(std::ostream& out, const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width;
  for (const std::vector<std::string>& row : rows) {
    if (row.size() > width.size()) width.resize(row.size(), 0);
    for (std::size_t i = 0; i < row.size(); ++i) width[i] = std::max(width[i], row[i].size());
  }
  for (const std::vector<std::string>& row : rows) {
    std::string line;
    for (std::size_t i = 0; i < row.size(); ++i) {
      const std::string pad(width[i] - row[i].size(), ' ');
      line += i == 0 ? row[i] + pad : "  " + pad + row[i];
    }
    out << line.substr(0, line.find_last_not_of(' ') + 1) << '\n';
  }
}

void Progress::run(const std::string& what, int done, int total) {
  const std::string text = what + ": run " + std::to_string(done) + "/" + std::to_string(total);
  if (in_place_) {
    err_ << '\r' << text << std::string(drawn_ > text.size() ? drawn_ - text.size() : 0, ' ');
    drawn_ = text.size();
  } else if (done == total || done * 10 / total != (done - 1) * 10 / total) {
    err_ << text << '\n';
  }
  err_.flush();
}

void Progress::clear() {
  if (in_place_ && drawn_ > 0) err_ << '\r' << std::string(drawn_, ' ') << '\r' << std::flush;
  drawn_ = 0;
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
  pid_t pid = 0;
  const int spawned = spawnProgram(argv, actions, pid);
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
  if (result.errors.size() > 2000) result.errors.erase(0, result.errors.size() - 2000);
  result.status = waitForExit(pid);
  return result;
}

std::string plot(const std::string& script, const std::vector<std::string>& arguments) {
  const std::string python = "/usr/bin/python3";
  if (!fs::exists(python)) return "plots not drawn: " + python + " is not installed";
  std::vector<std::string> argv = {python, LEGKIT_SOURCE_DIR "/tools/plots/" + script};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  const ProgramResult r = runProgram(argv);
  if (r.status == 0) return "";
  if (r.errors.find("No module named 'matplotlib'") != std::string::npos) {
    return "plots not drawn: python3-matplotlib is not installed";
  }
  // The last lines of the script's errors say what failed (a traceback ends with the exception).
  std::vector<std::string> lines;
  std::istringstream errors(r.errors);
  for (std::string line; std::getline(errors, line);) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
  }
  std::string tail;
  const std::size_t first = lines.size() > 3 ? lines.size() - 3 : 0;
  for (std::size_t i = first; i < lines.size(); ++i) tail += "\n  " + lines[i];
  std::string status = r.status < 0 ? "was killed or could not be started"
                                    : "exited with status " + std::to_string(r.status);
  return "plots FAILED: " + script + " " + status +
         (tail.empty() ? " and said nothing" : ":" + tail);
}

}  // namespace legkit::tools
