// What the kit's readers check before they open a file (issue 23 item 10): that it is a regular
// file, and, for the files read whole into memory (a settings file, a robot model), that it is not
// larger than a cap. A directory opens as a stream that fails on its first read
// ("basic_filebuf::underflow ... Is a directory", without the path), a FIFO blocks in open() until
// something writes to it, and a device such as /dev/zero never ends: each is refused up front,
// with a message naming the path.
#pragma once

#include <cstddef>
#include <filesystem>
#include <istream>
#include <string>
#include <system_error>

namespace legkit::io {

// Why `path` is not an input file the kit reads, or "" when it is a regular file (symbolic links
// followed) or does not exist (opening it says so then).
inline std::string notARegularFile(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status) || fs::is_regular_file(status)) return "";
  if (fs::is_directory(status)) return "is a directory, not a file";
  if (fs::is_fifo(status)) {
    return "is a FIFO (named pipe), not a regular file (reading it would wait for a writer)";
  }
  if (fs::is_character_file(status) || fs::is_block_file(status)) {
    return "is a device, not a regular file";
  }
  if (fs::is_socket(status)) return "is a socket, not a regular file";
  return "is not a regular file";
}

// The most a settings file or a robot model may hold: 16 MiB (the kit's largest is 40 kB).
constexpr std::size_t kMaxTextFileBytes = std::size_t{16} << 20;

// "is larger than the 16 MiB (16777216 bytes) a <what> may be"
inline std::string tooLarge(const char* what) {
  return "is larger than the 16 MiB (" + std::to_string(kMaxTextFileBytes) + " bytes) a " +
         std::string(what) + " may be; nothing beyond that is read";
}

// Reads the rest of `in` into `out`, at most `cap` bytes: false (and `out` cut) when the stream
// holds more.
inline bool readAtMost(std::istream& in, std::size_t cap, std::string& out) {
  out.clear();
  char buffer[1 << 16];
  while (in) {
    in.read(buffer, sizeof buffer);
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n > cap - out.size()) return false;
    out.append(buffer, n);
  }
  return true;
}

}  // namespace legkit::io
