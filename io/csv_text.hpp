// Small text helpers shared by the kit's strict CSV readers (the log, the pose file, Allan input):
// how a field is trimmed, how a number is printed back, and how a bad field is quoted in a message.
#pragma once

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

}  // namespace legkit::io
