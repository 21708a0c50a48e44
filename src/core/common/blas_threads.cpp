#include "cloth_hair_sim/core/common/blas_threads.h"

#include <mutex>

#include <dlfcn.h>

namespace chs {
namespace {

void setBlasThreads(int threads) {
  static const auto set =
      reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set) set(threads);
}

}  // namespace

void keepCholmodTeamsSmall() {
  thread_local bool done = false;
  if (done) return;
  static const auto set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "omp_set_dynamic"));
  if (set) set(1);
  done = true;
}

void holdBlasToOneThread() {
  static std::once_flag once;
  std::call_once(once, [] { setBlasThreads(1); });
}

}  // namespace chs
