// simulate: steps the bodies of a simulation scene together in one World among scripted
// colliders and writes per-frame meshes, a JSON report and pictures. Exit status: 0 completed,
// 2 stopped early (a step that diverged even when halved, or a frame over its substep budget;
// every frame finished so far is kept and the report says where and why), 1 bad input or any
// other error (message on stderr).
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/mesh_writer.h"
#include "cloth_hair_sim/core/io/simulation_plots.h"
#include "cloth_hair_sim/core/io/simulation_report.h"
#include "cloth_hair_sim/core/io/simulation_scene.h"
#include "cloth_hair_sim/core/simulation/simulation_run.h"

namespace {

constexpr int kCompleted = 0, kBadInput = 1, kStopped = 2;
namespace fs = std::filesystem;

struct Options {
  std::string scene;
  std::string out;
  std::string format = "obj";
  std::string render = "0,last";
  std::optional<double> duration;
  bool quiet = false;
};

// "0,12,last" (or "none") as frame numbers; last is numFrames, or the last frame reached.
struct RenderList {
  std::set<int> frames;
  bool last = false;
};

RenderList parseRenderList(const std::string& text, int frames) {
  RenderList r;
  if (text == "none") return r;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item == "last") {
      r.last = true;
      continue;
    }
    std::size_t used = 0;
    int k = -1;
    try {
      k = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || item.empty() || k < 0 || k > frames)
      throw chs::InputError("--render-frames: '" + item + "' is not a frame number 0.." +
                            std::to_string(frames) + ", last or none");
    r.frames.insert(k);
  }
  return r;
}

std::string frameFile(const std::string& body, int frame, const std::string& ext) {
  char number[16];
  std::snprintf(number, sizeof number, "%04d", frame);
  return body + "_" + number + "." + ext;
}

struct Frame {
  int index = 0;
  std::vector<chs::DisplaySurface> surfaces;
  std::vector<chs::rod::Polylines> hair;
  std::vector<Eigen::Isometry3d> poses;
};

int run(const Options& opt) {
  const auto run_start = std::chrono::steady_clock::now();
  chs::SimulationScene scene = chs::loadSimulationScene(opt.scene);
  if (opt.duration) {
    if (!(*opt.duration > 0.0)) throw chs::InputError("--duration: must be positive (s)");
    scene.duration = *opt.duration;
  }
  const RenderList render = parseRenderList(opt.render, scene.numFrames());
  const fs::path dir =
      opt.out.empty() ? fs::path("simulate_output") / scene.name : fs::path(opt.out);
  std::error_code ec;
  fs::create_directories(dir / "frames", ec);
  if (ec) throw chs::InputError(dir.string() + ": cannot create output directory: " + ec.message());

  chs::SimulationRun sim(scene);
  std::vector<std::string> names;
  long vertices = 0;
  for (const auto& b : scene.bodies) {
    names.push_back(b.name);
    vertices += b.problem.mesh.numVertices();
  }
  long strands = 0, strand_vertices = 0;
  for (const auto& h : scene.hair) {
    names.push_back(h.name);
    strands += static_cast<long>(h.strands.size());
    for (const auto& strand : h.strands) strand_vertices += static_cast<long>(strand.size());
  }
  if (!opt.quiet)
    std::cerr << "simulate: scene " << scene.name << ", " << scene.bodies.size() << " bodies ("
              << vertices << " control points), " << scene.hair.size() << " hair (" << strands
              << " strands, " << strand_vertices << " vertices), " << scene.colliders.size()
              << " colliders, " << sim.numFrames() << " frames of " << 1.0 / scene.frame_rate
              << " s, grid dx " << sim.world().gridSpacing() << " m" << std::endl;

  chs::SimulationSummary summary;
  summary.mesh_format = opt.format;
  const std::string title = scene.name;
  auto picture = [&](const std::string& what, const auto& draw) {
    try {
      draw();
    } catch (const std::exception& e) {
      std::cerr << "simulate: warning: no " << what << ": " << e.what() << std::endl;
      summary.notes.push_back("no " + what + ": " + e.what());
    }
  };
  auto renderFrame = [&](const Frame& f) {
    char name[32], caption[64];
    std::snprintf(name, sizeof name, "render_%04d.png", f.index);
    std::snprintf(caption, sizeof caption, ", frame %d, t = %.3f s", f.index,
                  f.index / scene.frame_rate);
    picture(name, [&] {
      chs::plotSimulationFrame(f.surfaces, f.hair, names, scene.colliders, f.poses,
                               (dir / name).string(), title + caption);
    });
  };
  // Meshes of the frame just reached, its picture if asked for; kept for a final "last".
  Frame last;
  auto output = [&](int index) {
    last.index = index;
    last.surfaces.clear();
    for (int b = 0; b < sim.numBodies(); ++b) {
      last.surfaces.push_back(sim.body(b).displaySurface());
      const std::string path = (dir / "frames" / frameFile(names[b], index, opt.format)).string();
      if (opt.format == "ply")
        chs::writeSurfacePly(path, last.surfaces.back());
      else
        chs::writeSurfaceObj(path, last.surfaces.back());
    }
    last.hair.clear();
    for (int h = 0; h < sim.numHair(); ++h) {
      chs::rod::Polylines strands;
      for (int s = 0; s < sim.hair(h).numStrands(); ++s)
        strands.push_back(sim.hair(h).strand(s).positions());
      const std::string path =
          (dir / "frames" / frameFile(names[sim.numBodies() + h], index, opt.format)).string();
      if (opt.format == "ply")
        chs::writeStrandsPly(path, strands);
      else
        chs::writeStrandsObj(path, strands);
      last.hair.push_back(std::move(strands));
    }
    last.poses = sim.colliderPoses();
    if (render.frames.count(index)) renderFrame(last);
  };

  summary.frames.push_back(sim.record());
  output(0);
  double stepping = 0.0;
  while (!sim.finished()) {
    const chs::FrameRecord rec = sim.advanceFrame();
    if (sim.stopped()) break;
    summary.frames.push_back(rec);
    stepping += rec.wall_time_s;
    output(rec.frame);
    if (!opt.quiet) {
      const double rtf = stepping > 0.0 ? rec.time / stepping : 0.0;
      const double eta = stepping / rec.frame * (sim.numFrames() - rec.frame);
      std::fprintf(stderr,
                   "simulate: frame %d/%d  t %.4f s  substeps %d  wall %.1f ms  real-time "
                   "factor %.3g  ETA %.1f s\n",
                   rec.frame, sim.numFrames(), rec.time, rec.substeps, 1e3 * rec.wall_time_s, rtf,
                   eta);
    }
  }
  if (render.last && !render.frames.count(last.index)) renderFrame(last);
  summary.completed = !sim.stopped();
  summary.stop_reason = sim.stopReason();
  summary.stop_time = sim.world().time();
  picture("energy plot",
          [&] { chs::plotEnergy(summary.frames, names, (dir / "energy.png").string(), title); });
  picture("timing plot",
          [&] { chs::plotTiming(summary.frames, (dir / "timing.png").string(), title); });
  summary.run_wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();
  chs::writeSimulationReport((dir / "report.json").string(), scene, summary);

  const double sim_time = summary.frames.back().time;
  if (!opt.quiet)
    std::cerr << "simulate: " << sim_time << " s simulated in " << stepping
              << " s of stepping (real-time factor " << (stepping > 0 ? sim_time / stepping : 0)
              << "); results in " << dir.string() << std::endl;
  if (sim.stopped()) {
    std::cerr << "simulate: stopped: " << sim.stopReason() << "; frames 0.." << last.index
              << " are kept in " << (dir / "frames").string() << std::endl;
    return kStopped;
  }
  return kCompleted;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  CLI::App app{
      "simulate: steps a scene's garments and hair as bodies of one world among scripted "
      "colliders and writes per-frame meshes and strands, report.json and pictures"};
  app.add_option("scene", opt.scene, "scene file (YAML, see io/simulation_scene.h)")->required();
  app.add_option("--out", opt.out, "output directory (default simulate_output/<scene name>)");
  app.add_option("--format", opt.format, "per-frame mesh format")
      ->check(CLI::IsMember({"obj", "ply"}));
  app.add_option("--render-frames", opt.render,
                 "frames to render as PNG: numbers and 'last', comma-separated, or 'none'")
      ->capture_default_str();
  app.add_option("--duration", opt.duration, "simulated time [s], instead of the scene's");
  app.add_flag("--quiet", opt.quiet, "no progress lines");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "simulate: bad input: " << e.what() << "\n" << app.help();
    return kBadInput;
  }
  try {
    return run(opt);
  } catch (const chs::InputError& e) {
    std::cerr << "simulate: bad input: " << e.what() << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "simulate: error: " << e.what() << std::endl;
  }
  return kBadInput;
}
