#include "cloth_hair_sim/core/io/drape_report.h"

#include <cmath>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace {

nlohmann::json vec(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

// JSON has no NaN/Inf: a diverged solve must still give a readable report.
nlohmann::json num(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
}

}  // namespace

std::string drapeReportJson(const DrapeResult& r, const ReportContext& c) {
  using nlohmann::json;
  json j;
  j["scene"] = c.scene_name;
  j["scene_file"] = c.scene_file;
  j["method"] = c.method;
  j["converged"] = r.converged;
  j["status"] = r.status;
  j["iterations"] = r.iterations;
  j["coarse_iterations"] = r.coarse_iterations;
  j["load_steps"] = r.load_steps;
  j["load_factor"] = num(r.load_factor);
  j["residual"] = num(r.residual);
  j["wall_time_s"] = num(r.wall_time_s);
  if (!r.stability.verdict.empty())  // the FEM shell and the solid shell's energy scheme
    j["stability"] = {{"assessed", r.stability.assessed},
                      {"lowest_eigenvalue",
                       r.stability.assessed ? num(r.stability.lowest_eigenvalue) : json(nullptr)},
                      {"negative_eigenvalues", r.stability.negative_eigenvalues},
                      {"stable", r.stability.stable},
                      {"verdict", r.stability.verdict},
                      {"scaling", "tangent symmetrised and scaled to unit diagonal"}};
  j["mesh"] = {{"vertices", c.vertices}, {"quads", c.quads}};
  json settings = json::object(), material = json::object();
  for (const auto& [k, v] : c.settings) settings[k] = num(v);
  for (const auto& [k, v] : c.material) material[k] = num(v);
  j["settings"] = settings;
  if (!c.drape_metrics.empty()) {
    json metrics = json::object();
    for (const auto& [k, v] : c.drape_metrics) metrics[k] = num(v);
    j["drape_metrics"] = metrics;
  }
  if (!c.seam_metrics.empty()) {
    json metrics = json::object();
    for (const auto& [k, v] : c.seam_metrics) metrics[k] = num(v);
    j["seams"] = metrics;
  }
  j["material"] = material;
  j["colliders"] = c.colliders;

  if (!r.positions.empty()) {
    Eigen::Vector3d lo = r.positions.front(), hi = lo;
    for (const auto& p : r.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    j["draped_bounding_box"] = {{"min", vec(lo)}, {"max", vec(hi)}};
  }

  json history = json::array();
  for (const auto& e : r.history)
    history.push_back({{"load_step", e.load_step},
                       {"load_factor", num(e.load_factor)},
                       {"iteration", e.iteration},
                       {"residual", num(e.residual)},
                       {"active_contacts", e.active_contacts}});
  j["residual_history"] = history;

  json per_vertex = json::array();
  std::map<int, Eigen::Vector3d> per_surface;
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (const auto& rc : r.reactions) {
    per_vertex.push_back(
        {{"vertex", rc.vertex}, {"surface", rc.surface}, {"force", vec(rc.force)}});
    auto it = per_surface.emplace(rc.surface, Eigen::Vector3d::Zero()).first;
    it->second += rc.force;
    total += rc.force;
  }
  json surfaces = json::array();
  for (const auto& [s, f] : per_surface) surfaces.push_back({{"surface", s}, {"force", vec(f)}});
  j["contact_reactions"] = {{"vertices", per_vertex},
                            {"per_surface", surfaces},
                            {"total", vec(total)},
                            {"count", r.reactions.size()}};
  j["notes"] = c.notes;
  return j.dump(2);
}

void writeDrapeReport(const std::string& path, const DrapeResult& result,
                      const ReportContext& context) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot open for writing");
  out << drapeReportJson(result, context) << '\n';
  out.close();
  if (!out) throw InputError(path + ": write failed");
}

}  // namespace chs
