#pragma once

namespace chs {

// The BLAS's own threads. Debian's OpenBLAS (pthread build) starts threads of its own, which spin
// in sched_yield against TBB's while the other stages run; CHOLMOD's supernodal factorisation is
// its one user here. The BLAS is therefore held to one thread, and a factorisation may borrow
// more while it runs (ScopedBlasThreads). Looked up at run time: any other BLAS has no such call
// and is left alone.

// Holds the BLAS to one thread from the first call on (once per process).
void holdBlasToOneThread();

// CHOLMOD's supernodal factorisation opens OpenMP parallel regions with a team of 4 compiled in
// (CHOLMOD_OMP_NUM_THREADS; OMP_NUM_THREADS does not bound it) round loops as short as clearing a
// column map. On 2 cores its threads then spend most of a small factorisation waking and waiting
// on futexes: the tablecloth's static drape made 147 000 context switches and took 3.8 s, 480
// and 1.05 s with OpenMP's dynamic adjustment on (OMP_DYNAMIC), which lets the runtime give a
// region fewer threads than it asks for when the cores are busy. Turns that on for the calling
// thread (OpenMP's setting is per thread), once; call before CHOLMOD factorises.
void keepCholmodTeamsSmall();

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
