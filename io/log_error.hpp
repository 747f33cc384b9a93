// The one exception the log reader and writer throw: it says which file, which line and which
// column, and what was expected there.
#pragma once

#include <stdexcept>
#include <string>

namespace legkit::io {

class LogError : public std::runtime_error {
 public:
  // line is 1-based (0: the problem is not tied to a line); column is a column name or empty.
  LogError(std::string file, int line, std::string column, const std::string& what)
      : std::runtime_error(format(file, line, column, what)),
        file_(std::move(file)),
        line_(line),
        column_(std::move(column)) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& column() const { return column_; }

 private:
  // "<file>:<line>: column '<column>': <what>"
  static std::string format(const std::string& file, int line, const std::string& column,
                            const std::string& what) {
    std::string s = file;
    if (line > 0) s += ":" + std::to_string(line);
    s += ": ";
    if (!column.empty()) s += "column '" + column + "': ";
    return s + what;
  }

  std::string file_;
  int line_;
  std::string column_;
};

}  // namespace legkit::io
