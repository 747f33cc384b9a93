#include "io/log_writer.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "io/log_columns.hpp"
#include "io/log_error.hpp"

namespace legkit::io {
namespace {

// Shortest decimal text that parses back to exactly x (std::to_chars round-trip guarantee).
void appendNumber(std::string& out, double x) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), x);
  if (ec != std::errc()) throw std::logic_error("to_chars failed");
  out.append(buffer, end);
}

}  // namespace

void writeLog(std::ostream& out, const Log& log, const std::string& destination) {
  std::vector<Column> columns;
  try {
    columns = columnsOf(log.layout);
  } catch (const std::invalid_argument& e) {
    throw LogError(destination, 0, "", e.what());
  }
  int line = 0;
  for (const std::string& comment : log.comments) {
    ++line;
    if (comment.find_first_of("\r\n") != std::string::npos) {
      throw LogError(destination, line, "", "a comment must not contain a line break");
    }
    out << "# " << comment << '\n';
  }
  std::string text;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) text += ',';
    text += columns[i].name;
  }
  out << text << '\n';
  ++line;
  for (std::size_t r = 0; r < log.rows.size(); ++r) {
    const LogRow& row = log.rows[r];
    ++line;
    if (r > 0 && !(row.t > log.rows[r - 1].t)) {
      throw LogError(destination, line, "t",
                     "timestamps must strictly increase (row " + std::to_string(r) + ")");
    }
    text.clear();
    for (std::size_t i = 0; i < columns.size(); ++i) {
      const double value = valueOf(row, columns[i]);
      if (!std::isfinite(value)) {
        throw LogError(destination, line, columns[i].name,
                       "cannot write a NaN or inf (row " + std::to_string(r) + ")");
      }
      const Field field = columns[i].field;
      if ((field == Field::kGtFn || field == Field::kGtFt || field == Field::kGtSlip) &&
          value < 0.0) {
        throw LogError(destination, line, columns[i].name,
                       "cannot write a negative magnitude (row " + std::to_string(r) + ")");
      }
      if (i > 0) text += ',';
      appendNumber(text, value);
    }
    text += '\n';
    out << text;
  }
  out.flush();
  if (!out) throw LogError(destination, 0, "", "write error");
}

void writeLog(const std::string& path, const Log& log) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw LogError(path, 0, "", "cannot open the file for writing");
  writeLog(out, log, path);
}

}  // namespace legkit::io
