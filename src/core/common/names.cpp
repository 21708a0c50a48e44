#include "cloth_hair_sim/core/common/names.h"

#include <cctype>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

void checkName(const std::string& name) {
  constexpr std::size_t kMaxLength = 64;
  const std::string rule = " (a name is a letter, then letters, digits or '_')";
  if (name.empty()) throw InputError("a name is needed" + rule);
  if (name.size() > kMaxLength)
    throw InputError("name: longer than " + std::to_string(kMaxLength) + " characters");
  if (!std::isalpha(static_cast<unsigned char>(name[0])))
    throw InputError("name: starts with '" + name.substr(0, 1) + "'" + rule);
  for (std::size_t i = 1; i < name.size(); ++i) {
    const unsigned char c = name[i];
    if (!std::isalnum(c) && c != '_')
      throw InputError(
          "name: " + (c == ' ' ? std::string("a space") : "'" + name.substr(i, 1) + "'") +
          " at position " + std::to_string(i + 1) + rule);
  }
}

}  // namespace chs
