#include "cloth_hair_sim/core/io/simulation_report.h"

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace {

// JSON has no NaN/Inf: a diverged run must still give a readable report.
nlohmann::json num(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
}

nlohmann::json vec(const Eigen::Vector3d& v) {
  return {num(v.x()), num(v.y()), num(v.z())};
}

}  // namespace

std::string simulationReportJson(const SimulationScene& scene, const SimulationSummary& s) {
  using nlohmann::json;
  json j;
  j["scene"] = scene.name;
  j["scene_file"] = scene.file;
  j["status"] = s.completed ? "completed" : "stopped";
  if (!s.completed)
    j["stop"] = {{"reason", s.stop_reason},
                 {"time_s", num(s.stop_time)},
                 {"last_complete_frame", s.frames.empty() ? 0 : s.frames.back().frame}};
  j["duration_s"] = scene.duration;
  j["frame_rate"] = scene.frame_rate;
  j["frames_planned"] = scene.numFrames();
  j["mesh_format"] = s.mesh_format;
  j["gravity"] = vec(scene.gravity);
  j["world"] = {{"grid_spacing_m", scene.world.grid_spacing},
                {"kernel_degree", scene.world.kernel_degree},
                {"body_friction", scene.world.body_friction},
                {"contact_distance_m", scene.world.contact_distance},
                {"damping_per_s", scene.shell.damping},
                {"integration", timeIntegrationName(scene.shell.integration)},
                {"safety", scene.shell.safety},
                {"cfl", scene.shell.cfl},
                {"max_substeps_per_frame", scene.max_substeps_per_frame}};
  json bodies = json::array();
  for (const auto& b : scene.bodies)
    bodies.push_back({{"name", b.name},
                      {"kind", "garment"},
                      {"material", b.material_name},
                      {"vertices", b.problem.mesh.numVertices()},
                      {"quads", b.problem.mesh.numQuads()},
                      {"pins", b.problem.bc.pinned.size()}});
  for (const auto& h : scene.hair) {
    long vertices = 0;
    for (const auto& strand : h.strands) vertices += static_cast<long>(strand.size());
    bodies.push_back({{"name", h.name},
                      {"kind", "hair"},
                      {"material", h.material_name},
                      {"strands", h.strands.size()},
                      {"vertices", vertices},
                      {"roots", h.roots},
                      {"continuum", h.continuum.enabled}});
  }
  j["bodies"] = bodies;
  json colliders = json::array();
  for (const auto& c : scene.colliders)
    colliders.push_back({{"name", c.name},
                         {"kind", c.kind},
                         {"friction", c.friction},
                         {"moving", c.motion.moves()}});
  j["colliders"] = colliders;

  json frames = json::array();
  double stepping = 0.0;
  long substeps = 0, rollbacks = 0;
  for (const FrameRecord& f : s.frames) {
    json jf = {{"frame", f.frame},
               {"time_s", num(f.time)},
               {"wall_time_s", f.wall_time_s},
               {"substeps", f.substeps},
               {"rollbacks", f.rollbacks},
               {"unconverged_steps", f.unconverged},
               {"kinetic_energy_J", num(f.kinetic_energy)}};
    json jb = json::object();
    for (std::size_t i = 0; i < f.bodies.size() && i < scene.bodies.size() + scene.hair.size(); ++i)
      jb[i < scene.bodies.size() ? scene.bodies[i].name
                                 : scene.hair[i - scene.bodies.size()].name] = {
          {"kinetic_energy_J", num(f.bodies[i].kinetic_energy)},
          {"deepest_penetration_m", num(f.bodies[i].deepest_penetration)},
          {"largest_stretch", num(f.bodies[i].largest_stretch)}};
    jf["bodies"] = jb;
    json jc = json::object();
    for (std::size_t i = 0; i < f.collider_loads.size() && i < scene.colliders.size(); ++i)
      jc[scene.colliders[i].name] = {{"force_N", vec(f.collider_loads[i].force)},
                                     {"moment_Nm", vec(f.collider_loads[i].moment)}};
    jf["colliders"] = jc;
    frames.push_back(jf);
    stepping += f.wall_time_s;
    substeps += f.substeps;
    rollbacks += f.rollbacks;
  }
  j["frames"] = frames;
  // Totals over the completed frames (a stopped run's partial frame is in stop only).
  const double sim_time = s.frames.empty() ? 0.0 : s.frames.back().time;
  const int stepped = s.frames.empty() ? 0 : static_cast<int>(s.frames.size()) - 1;
  j["totals"] = {{"frames_written", s.frames.size()},
                 {"sim_time_s", num(sim_time)},
                 {"stepping_wall_time_s", stepping},
                 {"run_wall_time_s", s.run_wall_time_s},
                 {"mean_wall_time_per_frame_s", stepped > 0 ? stepping / stepped : 0.0},
                 {"real_time_factor", stepping > 0.0 ? num(sim_time / stepping) : json()},
                 {"substeps", substeps},
                 {"rollbacks", rollbacks}};
  j["notes"] = s.notes;
  return j.dump(2);
}

void writeSimulationReport(const std::string& path, const SimulationScene& scene,
                           const SimulationSummary& summary) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot open for writing");
  out << simulationReportJson(scene, summary) << '\n';
  out.close();
  if (!out) throw InputError(path + ": write failed");
}

}  // namespace chs
