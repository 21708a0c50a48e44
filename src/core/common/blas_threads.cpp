#include "cloth_hair_sim/core/common/blas_threads.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <mutex>

#include <dlfcn.h>

namespace chs {
namespace {

void setBlasThreads(int threads) {
  static const auto set =
      reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set) set(threads);
}

thread_local int inline_depth = 0;
std::atomic<long> inlined{0};

}  // namespace

InlineOpenMpRegions::InlineOpenMpRegions() {
  ++inline_depth;
}

InlineOpenMpRegions::~InlineOpenMpRegions() {
  --inline_depth;
}

long inlinedOpenMpRegions() {
  return inlined.load();
}

void holdBlasToOneThread() {
  static std::once_flag once;
  std::call_once(once, [] { setBlasThreads(1); });
}

}  // namespace chs

// libgomp's entry point for `#pragma omp parallel` (GCC 4.9 and later): see InlineOpenMpRegions.
// The core library precedes libgomp (a dependency of CHOLMOD's) in the lookup order of every
// program that links it, so CHOLMOD's calls land here.
extern "C" __attribute__((visibility("default"))) void GOMP_parallel(void (*fn)(void*), void* data,
                                                                     unsigned num_threads,
                                                                     unsigned flags) {
  using Entry = void (*)(void (*)(void*), void*, unsigned, unsigned);
  using Count = int (*)();
  static const Entry next = reinterpret_cast<Entry>(dlsym(RTLD_NEXT, "GOMP_parallel"));
  static const Count team_size = reinterpret_cast<Count>(dlsym(RTLD_NEXT, "omp_get_num_threads"));
  if (chs::inline_depth > 0 && (!team_size || team_size() == 1)) {
    ++chs::inlined;
    fn(data);
    return;
  }
  if (!next) {
    std::fprintf(stderr, "cloth_hair_sim: GOMP_parallel called without libgomp loaded\n");
    std::abort();
  }
  next(fn, data, num_threads, flags);
}
