// Writing a log CSV that reads back bit for bit: every number is written with the shortest
// decimal form that parses back to the same double.
#pragma once

#include <ostream>
#include <string>

#include "io/log.hpp"

namespace legkit::io {

// Writes the header (the layout's columns, io/log_columns.hpp) and one line per row. Throws
// LogError for what the reader would reject: an invalid layout, a non-finite value, timestamps
// not strictly increasing, a negative true force or slip speed (contact_truth group), a comment
// with a line break; and when the file cannot be written.
void writeLog(const std::string& path, const Log& log);

// The same to a stream; destination names it in error messages.
void writeLog(std::ostream& out, const Log& log, const std::string& destination = "<stream>");

}  // namespace legkit::io
