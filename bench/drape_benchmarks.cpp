// Drape benchmarks (run by hand with `make bench`, never by ctest): whole static drapes of the
// seed scenes with both methods, and micro-benchmarks of the FEM Newton iteration's two costs,
// the tangent assembly and the sparse LU solve, to say where the FEM time goes.
//
// Whole drapes run once per benchmark (Iterations(1)): they take seconds to minutes, and a
// repeated run would only measure the same deterministic path again. Counters report the work
// (Newton iterations, load steps) and whether the drape converged, so a fast non-converged run
// cannot pass for a result.
#include <chrono>
#include <cstdlib>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <Eigen/CholmodSupport>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <Eigen/UmfPackSupport>

#include "cloth_hair_sim/core/common/blas_threads.h"
#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/fem_shell/shell_model.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "cloth_hair_sim/core/particle/particle_static_solver.h"

namespace {

std::string scenePath(const char* name) {
  return std::string(CHS_SOURCE_DIR) + "/scenes/" + name;
}

// Thrown from the progress callback to stop a drape that overruns its time budget; the solver
// holds only RAII state, so unwinding through it is safe.
struct TimeLimitExceeded {
  chs::ProgressEvent last;
};

// Budget of one whole drape in seconds: CHS_BENCH_TIME_LIMIT, default 900 (the pedestal 48 may
// take minutes on a shared two-core machine).
double timeLimit() {
  const char* env = std::getenv("CHS_BENCH_TIME_LIMIT");
  return env ? std::atof(env) : 900.0;
}

void reportResult(benchmark::State& state, const chs::DrapeResult& r) {
  state.counters["converged"] = r.converged ? 1 : 0;
  state.counters["iterations"] = r.iterations;
  state.counters["load_steps"] = r.load_steps;
  state.counters["load_factor"] = r.load_factor;
  state.counters["residual"] = r.residual;
  state.counters["solver_wall_s"] = r.wall_time_s;
  state.SetLabel(r.converged ? "converged" : "NOT CONVERGED: " + r.status);
}

// One FEM drape of a scene with TBB limited to state.range(0) threads.
void femDrape(benchmark::State& state, const char* scene_file) {
  const chs::Scene scene = chs::loadScene(scenePath(scene_file));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  state.counters["nodes"] = scene.problem.mesh.numVertices();
  state.counters["threads"] = static_cast<double>(state.range(0));
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const double limit = timeLimit();
    auto watchdog = [&](const chs::ProgressEvent& e) {
      if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > limit)
        throw TimeLimitExceeded{e};
    };
    try {
      const chs::DrapeResult r = chs::solveFemShell(scene.problem, scene.fem_shell, watchdog);
      reportResult(state, r);
    } catch (const TimeLimitExceeded& t) {
      state.counters["converged"] = 0;
      state.counters["load_factor"] = t.last.load_factor;
      state.counters["load_steps"] = t.last.load_step;
      state.SetLabel("NOT CONVERGED: time limit of " + std::to_string(limit) +
                     " s exceeded at load factor " + std::to_string(t.last.load_factor));
    }
  }
}

void BM_TableclothFem(benchmark::State& state) {
  femDrape(state, "tablecloth_fem.yaml");
}
BENCHMARK(BM_TableclothFem)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->Iterations(1)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kSecond);

void BM_Pedestal48Fem(benchmark::State& state) {
  femDrape(state, "pedestal_square_48.yaml");
}
BENCHMARK(BM_Pedestal48Fem)
    ->Arg(2)
    ->ArgName("threads")
    ->Iterations(1)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kSecond);

// The particle relaxation is serial: no thread variant.
void BM_TableclothParticle(benchmark::State& state) {
  const chs::Scene scene = chs::loadScene(scenePath("tablecloth_particle.yaml"));
  state.counters["nodes"] = scene.problem.mesh.numVertices();
  for (auto _ : state) reportResult(state, chs::solveParticleStatic(scene.problem, scene.particle));
}
BENCHMARK(BM_TableclothParticle)->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);

// The tablecloth's shell model at its flat reference state under the full load: assembly cost
// hardly depends on the state, and the tangent's sparsity pattern is fixed.
struct TableclothModel {
  chs::Scene scene = chs::loadScene(scenePath("tablecloth_fem.yaml"));
  chs::ShellModel model{scene.problem, scene.fem_shell.contact_stiffness};
};

// One linearisation: residual and load vector, with the tangent when range(1) is 1.
void BM_TableclothAssembly(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  auto m = std::make_unique<TableclothModel>();
  const bool with_k = state.range(1) != 0;
  Eigen::VectorXd R, F0;
  Eigen::SparseMatrix<double> K;
  for (auto _ : state) {
    m->model.linearize(1.0, R, F0, with_k ? &K : nullptr);
    benchmark::DoNotOptimize(R.data());
  }
  state.counters["dofs"] = m->model.size();
  if (with_k) state.counters["nnz"] = static_cast<double>(K.nonZeros());
}
BENCHMARK(BM_TableclothAssembly)
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->ArgNames({"threads", "with_K"})
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kMillisecond);

// The tablecloth's tangent and residual at its flat reference state under the full load.
struct TableclothTangent {
  Eigen::SparseMatrix<double> K;
  Eigen::VectorXd R;
  TableclothTangent() {
    auto m = std::make_unique<TableclothModel>();
    Eigen::VectorXd F0;
    m->model.linearize(1.0, R, F0, &K);
  }
};

// Numeric factorisation + one solve per iteration, the symbolic analysis done once (as the
// arc-length solver does) unless reanalyse is set.
template <class Solver>
void timeFactorisation(benchmark::State& state, Solver& solver,
                       const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
                       bool reanalyse = false) {
  Eigen::VectorXd x;
  solver.analyzePattern(A);
  for (auto _ : state) {
    if (reanalyse) solver.analyzePattern(A);
    solver.factorize(A);
    x = solver.solve(b);
    benchmark::DoNotOptimize(x.data());
  }
  if (solver.info() != Eigen::Success) state.SkipWithError("factorisation failed");
  state.counters["dofs"] = static_cast<double>(A.rows());
  state.counters["nnz"] = static_cast<double>(A.nonZeros());
}

// UMFPACK, what the solver uses. range(0) = 1: pattern analysis reused; 0: redone each time.
void BM_TableclothLuSolve(benchmark::State& state) {
  const TableclothTangent t;
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu;
  timeFactorisation(state, lu, t.K, t.R, state.range(0) == 0);
}
BENCHMARK(BM_TableclothLuSolve)
    ->Arg(1)
    ->Arg(0)
    ->ArgName("reuse_pattern")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// Eigen's supernodal SparseLU on the same tangent: range(0) 0 = COLAMD, 1 = AMD on A^T + A.
void BM_TableclothSparseLu(benchmark::State& state) {
  const TableclothTangent t;
  if (state.range(0) == 0) {
    Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
    timeFactorisation(state, lu, t.K, t.R);
  } else {
    Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::AMDOrdering<int>> lu;
    timeFactorisation(state, lu, t.K, t.R);
  }
}
BENCHMARK(BM_TableclothSparseLu)
    ->Arg(0)
    ->Arg(1)
    ->ArgName("amd")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// Symmetric factorisations of (K + K^T)/2, for scale: range(0) 0 = Eigen SimplicialLDLT (AMD),
// 1 = CHOLMOD supernodal LL^T.
void BM_TableclothSymmetric(benchmark::State& state) {
  const TableclothTangent t;
  const Eigen::SparseMatrix<double> S = 0.5 * (t.K + Eigen::SparseMatrix<double>(t.K.transpose()));
  if (state.range(0) == 0) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> f;
    timeFactorisation(state, f, S, t.R);
  } else {
    const chs::InlineOpenMpRegions serial;
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> f;
    timeFactorisation(state, f, S, t.R);
  }
}
BENCHMARK(BM_TableclothSymmetric)
    ->Arg(0)
    ->Arg(1)
    ->ArgName("cholmod")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
