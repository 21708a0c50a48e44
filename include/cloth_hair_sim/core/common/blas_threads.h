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

// CHOLMOD's supernodal factorisation opens OpenMP parallel regions with a team of 4 compiled in
// (CHOLMOD_OMP_NUM_THREADS; OMP_NUM_THREADS does not bound it) round loops as short as clearing a
// column map. On 2 cores its threads then spend most of a small factorisation waking and waiting
// on futexes: the tablecloth's static drape made 147 000 context switches and took 3.8 s, 480
// and 1.05 s with OpenMP's dynamic adjustment on (OMP_DYNAMIC), which lets the runtime give a
// region fewer threads than it asks for when the cores are busy. Turns that on for the calling
// thread (OpenMP's setting is per thread), once; call before CHOLMOD factorises.
void keepCholmodTeamsSmall();

}  // namespace chs
