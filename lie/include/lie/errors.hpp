// The one exception type of lie/: a matrix handed to a checked constructor is not in the group.
#pragma once

#include <stdexcept>
#include <string>

namespace lie {

class NotInGroup : public std::invalid_argument {
 public:
  explicit NotInGroup(const std::string& what) : std::invalid_argument(what) {}
};

}  // namespace lie
