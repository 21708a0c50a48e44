#pragma once

namespace chs {

// The BLAS's own threads. Debian's OpenBLAS (pthread build) starts threads of its own, which spin
// in sched_yield against TBB's while the other stages run; CHOLMOD's supernodal factorisation is
// its one user here. The BLAS is therefore held to one thread, and a factorisation may borrow
// more while it runs (ScopedBlasThreads). Looked up at run time: any other BLAS has no such call
// and is left alone.

// Holds the BLAS to one thread from the first call on (once per process).
void holdBlasToOneThread();

// Gives the BLAS `threads` threads for the scope, then one again; does nothing while a
// ConcurrentBlasCallers is alive: OpenBLAS's thread count is process-wide, and changing it under
// a BLAS call on another thread is not safe.
class ScopedBlasThreads {
 public:
  explicit ScopedBlasThreads(int threads);
  ~ScopedBlasThreads();
  ScopedBlasThreads(const ScopedBlasThreads&) = delete;
  ScopedBlasThreads& operator=(const ScopedBlasThreads&) = delete;

 private:
  bool changed_ = false;
};

// Marks a scope in which several threads may call the BLAS at once (the world stepping its bodies
// in parallel): the BLAS stays on one thread meanwhile.
class ConcurrentBlasCallers {
 public:
  ConcurrentBlasCallers();
  ~ConcurrentBlasCallers();
  ConcurrentBlasCallers(const ConcurrentBlasCallers&) = delete;
  ConcurrentBlasCallers& operator=(const ConcurrentBlasCallers&) = delete;
};

}  // namespace chs
