#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

namespace chs {

// Parallel sums that repeat bit for bit. Threads that each add whichever items work stealing
// gives them into an array of their own add them in another order in every run (and that
// round-off decided whether a strand stayed wrapped on a capstan). Here the items are cut into
// fixed contiguous chunks, one per allowed thread, each summed in item order into its own array,
// and the chunks' arrays are added in chunk order: the same result in every run with as many
// threads, and on one thread the same on every machine. The cost: no work stealing between the
// chunks. The grid transfer (mpm/transfers.cpp) showed none; the shell's other sums (forces,
// gradient, Hessian assembly) took 5-15 % longer per Lagrangian step of the towel this way, and
// stay as they were.

// The threads allowed: the task arena's, capped by tbb::global_control.
inline int allowedThreads() {
  return static_cast<int>(std::min<std::size_t>(
      tbb::this_task_arena::max_concurrency(),
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
}

// Calls body(chunk, begin, end) for chunks fixed contiguous ranges covering [0, n), chunk c
// being [c n / chunks, (c + 1) n / chunks), the chunks in parallel.
template <class Body>
void forFixedChunks(int n, int chunks, Body&& body) {
  tbb::parallel_for(
      tbb::blocked_range<int>(0, chunks, 1),
      [&](const tbb::blocked_range<int>& r) {
        for (int c = r.begin(); c != r.end(); ++c)
          body(c, static_cast<int>(static_cast<long>(c) * n / chunks),
               static_cast<int>(static_cast<long>(c + 1) * n / chunks));
      },
      tbb::simple_partitioner());
}

// The sum over the items [0, n) of their contributions to an array of `size` entries:
// add(array, begin, end) adds the contributions of items begin .. end - 1 to `array` (of size
// entries, `zero` at first).
template <class T, class Add>
std::vector<T> chunkedSum(int n, std::size_t size, const T& zero, Add&& add) {
  const int chunks = allowedThreads();
  std::vector<std::vector<T>> parts(chunks);
  forFixedChunks(n, chunks, [&](int c, int begin, int end) {
    parts[c].assign(size, zero);
    add(parts[c], begin, end);
  });
  for (int c = 1; c < chunks; ++c)
    for (std::size_t k = 0; k < size; ++k) parts[0][k] += parts[c][k];
  return std::move(parts[0]);
}

}  // namespace chs
