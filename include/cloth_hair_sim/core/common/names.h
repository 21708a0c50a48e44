#pragma once
#include <string>

namespace chs {

// One rule for every name a user gives a body, grasp or collider: it becomes a ROS topic
// segment (~grasp_wrench/<name>, ~garments/<name>/...), a marker namespace and a file stem, so
// it is a ROS base name: a letter, then letters, digits or '_', at most 64 characters.
// Throws InputError "name: ..." saying which character breaks the rule (callers say whose name).
void checkName(const std::string& name);

}  // namespace chs
