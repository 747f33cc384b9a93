#include "io/csv_text.hpp"

#include <charconv>
#include <limits>

#include "io/log_error.hpp"

namespace legkit::io {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::string numberText(double x) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), x);
  return ec == std::errc() ? std::string(buffer, end) : std::string("?");
}

std::string shown(std::string_view text) {
  constexpr std::size_t kMax = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < text.size() && i < kMax; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 0xf];
    }
  }
  out += '\'';
  if (text.size() > kMax) out += "... (" + std::to_string(text.size()) + " characters)";
  return out;
}

bool LineSource::next(std::string_view& line) {
  line_.clear();
  int c = buffer_.sbumpc();
  if (c == std::char_traits<char>::eof()) return false;
  // Line numbers are ints (LogError::line); a file of 2^31 line ends must not overflow them.
  if (number_ == std::numeric_limits<int>::max()) {
    throw LogError(source_, number_, "", "more lines than a line number can count");
  }
  while (c != std::char_traits<char>::eof() && c != '\n' && c != '\r') {
    line_.push_back(static_cast<char>(c));
    c = buffer_.sbumpc();
  }
  if (c == '\r' && buffer_.sgetc() == '\n') buffer_.sbumpc();
  if (++number_ == 1 && line_.compare(0, 3, "\xEF\xBB\xBF") == 0) line_.erase(0, 3);
  line = line_;
  bytes_ += line_.size() + 1;
  return true;
}

}  // namespace legkit::io
