// Small text helpers shared by the kit's strict CSV readers (the log, the pose file, Allan input):
// how a field is trimmed, how a number is printed back, and how a bad field is quoted in a message.
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <string_view>

namespace legkit::io {

// The field without leading or trailing spaces and tabs (and a trailing CR).
std::string_view trim(std::string_view s);

// The shortest text that reads back as the same double (std::to_chars).
std::string numberText(double x);

// A field as an error message quotes it: bytes that do not print are escaped (\xNN, NUL too) and
// anything past 40 characters is cut, so that a 100 kB field does not make a 100 kB message.
std::string shown(std::string_view text);

// Hands out the lines of a stream with their 1-based numbers, one at a time (the file is never
// held whole in memory). A line ends at LF, CR LF or a lone CR (old Mac files), so text files
// from every platform read alike; a UTF-8 byte-order mark before the first line is skipped.
// `source` names the stream in the LogError thrown past 2^31 - 1 lines (line numbers are ints).
class LineSource {
 public:
  LineSource(std::istream& in, const std::string& source) : buffer_(*in.rdbuf()), source_(source) {}
  bool next(std::string_view& line);
  int number() const { return number_; }
  std::size_t bytes() const { return bytes_; }  // read so far, about

 private:
  std::streambuf& buffer_;
  const std::string& source_;
  std::string line_;
  int number_ = 0;
  std::size_t bytes_ = 0;
};

}  // namespace legkit::io
