// drape: solves the static drape of a scene file and writes the draped mesh, a JSON report and
// pictures. Exit status: 0 converged, 2 not converged (results of the last state still
// written), 1 bad input or any other error (message on stderr).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/drape/drape_metrics.h"
#include "cloth_hair_sim/core/drape/seam_groups.h"
#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/io/drape_plots.h"
#include "cloth_hair_sim/core/io/drape_report.h"
#include "cloth_hair_sim/core/io/mesh_writer.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "cloth_hair_sim/core/particle/particle_static_solver.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_solver.h"

namespace {

constexpr int kConverged = 0, kBadInput = 1, kNotConverged = 2;

struct Options {
  std::string scene;
  std::optional<std::string> out;
  std::optional<std::string> method;
  bool quiet = false;
};

const char* kUsage =
    "usage: drape SCENE.yaml [--out DIR] [--method fem_shell|particle|solid_shell] [--quiet]\n";

Options parseArgs(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw chs::InputError(a + " needs a value\n" + kUsage);
      return argv[++i];
    };
    if (a == "--out")
      o.out = value();
    else if (a == "--method")
      o.method = value();
    else if (a == "--quiet")
      o.quiet = true;
    else if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      std::exit(0);
    } else if (!a.empty() && a[0] == '-')
      throw chs::InputError("unknown option " + a + "\n" + kUsage);
    else if (o.scene.empty())
      o.scene = a;
    else
      throw chs::InputError("more than one scene file given (" + o.scene + ", " + a + ")\n" +
                            kUsage);
  }
  if (o.scene.empty()) throw chs::InputError(std::string("no scene file given\n") + kUsage);
  return o;
}

chs::DrapeResult solve(const chs::Scene& scene, const chs::ProgressCallback& progress) {
  if (scene.problem.fabric && scene.method != chs::DrapeMethod::kSolidShell)
    throw chs::InputError("material: the orthotropic woven fabric " + scene.material_name +
                          " is supported by method solid_shell only");
  switch (scene.method) {
    case chs::DrapeMethod::kFemShell:
      return chs::solveFemShell(scene.problem, scene.fem_shell, progress);
    case chs::DrapeMethod::kParticle:
      return chs::solveParticleStatic(scene.problem, scene.particle, progress);
    case chs::DrapeMethod::kSolidShell:
      return chs::solveSolidShell(scene.problem, scene.solid_shell, progress);
  }
  throw chs::InputError("unknown method");
}

int run(int argc, char** argv) {
  const Options opt = parseArgs(argc, argv);
  chs::Scene scene = chs::loadScene(opt.scene);
  if (opt.method) scene.method = chs::parseMethod(*opt.method);
  const std::string method = chs::methodName(scene.method);
  const std::filesystem::path dir = opt.out ? *opt.out : scene.output.directory;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw chs::InputError(dir.string() + ": cannot create output directory: " + ec.message());

  if (!opt.quiet)
    std::cout << "drape: scene " << scene.name << ", method " << method << ", "
              << scene.problem.mesh.numVertices() << " vertices, " << scene.problem.mesh.numQuads()
              << " quads, material " << scene.material_name << std::endl;
  chs::ProgressCallback progress;
  if (!opt.quiet)
    progress = [](const chs::ProgressEvent& e) {
      std::printf("step %4d  load %.6f  iter %3d  residual %.3e  contacts %d%s\n", e.load_step,
                  e.load_factor, e.iteration, e.residual, e.active_contacts,
                  e.coarser_grids == 0 ? ""
                  : e.coarser_grids == 1
                      ? "  (coarser grid)"
                      : ("  (" + std::to_string(e.coarser_grids) + " grids coarser)").c_str());
      std::fflush(stdout);
    };
  const auto start = std::chrono::steady_clock::now();
  chs::DrapeResult result = solve(scene, progress);
  if (result.wall_time_s <= 0.0)
    result.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // An adaptive solve answers on its background mesh.
  const chs::QuadMesh& mesh = result.refined_mesh ? *result.refined_mesh : scene.problem.mesh;
  const std::vector<Eigen::Vector3d> positions =
      result.positions.size() == mesh.vertices.size() ? result.positions : mesh.vertices;

  chs::writeObj((dir / scene.output.obj).string(), mesh, positions);
  chs::writePly((dir / scene.output.ply).string(), mesh, positions);
  // The adaptive mesh as it ended: its own OBJ, and the picture draws it (a triangle as a quad
  // with its last corner twice).
  chs::QuadMesh pictured = mesh;
  if (!result.active_elements.empty() && result.positions.size() == mesh.vertices.size()) {
    chs::writeElementsObj((dir / "active_mesh.obj").string(), positions, result.active_elements);
    pictured.quads.clear();
    for (auto e : result.active_elements) {
      if (e[3] < 0) e[3] = e[2];
      pictured.quads.push_back(e);
    }
  }

  chs::ReportContext context;
  context.scene_name = scene.name;
  context.scene_file = scene.file;
  context.method = method;
  context.settings =
      scene.method == chs::DrapeMethod::kFemShell   ? chs::settingsList(scene.fem_shell)
      : scene.method == chs::DrapeMethod::kParticle ? chs::settingsList(scene.particle)
                                                    : chs::settingsList(scene.solid_shell);
  context.material = scene.problem.fabric ? chs::materialList(*scene.problem.fabric)
                                          : chs::materialList(scene.problem.material);
  for (const auto& c : scene.problem.colliders) context.colliders.push_back(c->describe());
  context.vertices = mesh.numVertices();
  context.quads = mesh.numQuads();
  if (result.refined_mesh)
    context.notes.push_back(
        "adaptive mesh: " + std::to_string(result.peak_active_nodes) +
        " nodes in use at most; draped.obj/ply hold the background mesh of " +
        std::to_string(mesh.numVertices()) +
        " nodes, active_mesh.obj and the picture the elements in use at the end");
  if (result.positions.size() != mesh.vertices.size())
    context.notes.push_back("the solver returned no positions: meshes show the reference state");

  if (!scene.colliders.empty()) {
    try {
      const chs::DrapeMetrics m =
          chs::measureDrape(mesh, positions, chs::supportOf(scene.colliders.front()));
      context.drape_metrics = {{"drape_coefficient", m.drape_coefficient},
                               {"folds", m.folds},
                               {"lowest_z", m.lowest_z},
                               {"highest_z", m.highest_z},
                               {"max_radius", m.max_radius}};
      if (!opt.quiet)
        std::printf("drape: drape coefficient %.3f, %d folds, lowest point %.2f mm\n",
                    m.drape_coefficient, m.folds, 1e3 * m.lowest_z);
    } catch (const chs::InputError&) {
      // A plane, sphere or capsule has no top face: no drape coefficient.
    }
  }
  if (!scene.problem.seams.empty()) {
    const chs::SeamGroups seams(scene.problem.mesh.numVertices(), scene.problem.seams);
    double lowest = positions.front().z();
    for (const auto& x : positions) lowest = std::min(lowest, x.z());
    context.seam_metrics = {{"pairs", static_cast<double>(seams.pairs().size())},
                            {"max_gap_m", seams.maxGap(positions)}};
    if (!opt.quiet)
      std::printf("drape: %zu seam pairs, largest seam gap %.3g m, lowest point %.4f m\n",
                  seams.pairs().size(), seams.maxGap(positions), lowest);
  }
  const std::string title = scene.name + " (" + method + ")";
  auto picture = [&](const std::string& what, const auto& draw) {
    try {
      draw();
    } catch (const std::exception& e) {
      std::cerr << "drape: warning: no " << what << ": " << e.what() << std::endl;
      context.notes.push_back("no " + what + ": " + e.what());
    }
  };
  picture("convergence plot", [&] {
    chs::plotConvergence(result, (dir / scene.output.convergence).string(), title,
                         scene.method == chs::DrapeMethod::kFemShell ? scene.fem_shell.tolerance
                         : scene.method == chs::DrapeMethod::kSolidShell
                             ? scene.solid_shell.tolerance
                             : 0.0);
  });
  picture("drape picture", [&] {
    chs::plotDrape(pictured, positions, scene.colliders, (dir / scene.output.picture).string(),
                   title);
  });
  chs::writeDrapeReport((dir / scene.output.report).string(), result, context);

  char eigen[64] = "";
  if (result.stability.assessed)
    std::snprintf(eigen, sizeof eigen, ", lowest eigenvalue %.4g",
                  result.stability.lowest_eigenvalue);
  if (!opt.quiet)
    std::cout << "drape: " << (result.converged ? "converged" : "NOT converged") << " after "
              << result.load_steps << " load steps, " << result.iterations << " iterations, "
              << result.wall_time_s << " s: " << result.status << "\n"
              << (!result.stability.verdict.empty()
                      ? "drape: stability: " + result.stability.verdict + eigen + "\n"
                      : std::string())
              << "drape: results in " << dir.string() << std::endl;
  if (!result.converged) std::cerr << "drape: not converged: " << result.status << std::endl;
  return result.converged ? kConverged : kNotConverged;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const chs::InputError& e) {
    std::cerr << "drape: bad input: " << e.what() << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "drape: error: " << e.what() << std::endl;
  }
  return kBadInput;
}
