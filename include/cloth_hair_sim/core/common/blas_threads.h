#pragma once

namespace chs {

// The BLAS's own threads. Debian's OpenBLAS (pthread build) starts threads of its own, which spin
// in sched_yield for a while after each call, against TBB's workers in the stages that follow;
// CHOLMOD's supernodal factorisation is its one user here. The BLAS is therefore held to one
// thread. (Lending it a second for each factorisation made the factorisation faster but whole
// runs slower: the node's Lagrangian demo simulated 4.3 s in 40 s of wall instead of 6.1-6.6 s,
// its BLAS worker spinning a third of a core; docs/BENCHMARKS.md.) Looked up at run time: any
// other BLAS has no such call and is left alone.

// Holds the BLAS to one thread from the first call on (once per process).
void holdBlasToOneThread();

// CHOLMOD's supernodal factorisation (SuiteSparse 5.12, Debian 12) opens an OpenMP parallel
// region with a team of 4 compiled in (CHOLMOD_OMP_NUM_THREADS, which OMP_NUM_THREADS does not
// bound) round loops as short as clearing a column map, thousands per factorisation. With a team
// of four on 2 cores the threads spent most of a small factorisation waking and waiting on
// futexes (the tablecloth's drape: 147 000 context switches, 3.8 s); OpenMP's dynamic adjustment
// shrank the teams, but every region still made libgomp look up the load and the affinity and
// wake its pool: 1.8 million futex and 0.56 million sysinfo and sched_getaffinity calls, 2.7 s of
// system time in the 50 x 50 cm drape on the disc (docs/BENCHMARKS.md, 2026-12-07). Nothing in
// CHOLMOD or libgomp turns the regions off, so the core library interposes libgomp's entry point
// for a parallel region, GOMP_parallel: while an InlineOpenMpRegions lives in a thread, the
// regions that thread opens run their body once, on the thread itself, as a team of one would
// (omp_get_thread_num() 0, omp_get_num_threads() 1: a worksharing loop takes all its iterations).
// Elsewhere, and in a thread already inside a team, the call goes on to libgomp unchanged.
// Hold one round each CHOLMOD factorisation.
class InlineOpenMpRegions {
 public:
  InlineOpenMpRegions();
  ~InlineOpenMpRegions();
  InlineOpenMpRegions(const InlineOpenMpRegions&) = delete;
  InlineOpenMpRegions& operator=(const InlineOpenMpRegions&) = delete;
};

// Parallel regions run inline so far in this process: 0 after a CHOLMOD factorisation means the
// interposition did not take (libgomp came first in the symbol lookup order).
long inlinedOpenMpRegions();

}  // namespace chs
