#pragma once
#include <atomic>

namespace chs {

// Set by another thread (a ROS action's cancel, a GUI's stop button) to ask a long solve to
// stop. The static solvers poll it once per iteration and return their last good state with
// DrapeResult::cancelled; a null flag means the solve runs to its end.
using CancelFlag = std::atomic<bool>;

inline bool cancelRequested(const CancelFlag* flag) {
  return flag != nullptr && flag->load(std::memory_order_relaxed);
}

}  // namespace chs
