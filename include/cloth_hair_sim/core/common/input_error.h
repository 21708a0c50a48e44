#pragma once
#include <stdexcept>
#include <string>

namespace chs {

// Thrown for input that makes no sense (bad file, broken mesh, nonsense material, ...).
// The message names the problem and, where there is one, the offending vertex or element,
// so that tools and the ROS node can report it and carry on.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace chs
