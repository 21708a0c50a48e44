#pragma once
#include <string>
#include <utility>
#include <vector>

#include "cloth_hair_sim/core/drape/drape_problem.h"

namespace chs {

// What the report says about the run besides the result itself.
struct ReportContext {
  std::string scene_name;
  std::string scene_file;
  std::string method;                                    // fem_shell | particle
  std::vector<std::pair<std::string, double>> settings;  // solver settings, by name
  std::vector<std::pair<std::string, double>> material;  // SI values, by name
  std::vector<std::string> colliders;                    // RigidSurface::describe()
  int vertices = 0;
  int quads = 0;
  std::vector<std::string> notes;  // e.g. pictures that could not be drawn
  // Drape coefficient, folds, lowest point... (core/drape/drape_metrics.h) when the first
  // collider is a table or pedestal; empty otherwise.
  std::vector<std::pair<std::string, double>> drape_metrics;
  // With seams: the number of sewn pairs and the largest distance between partners (m).
  std::vector<std::pair<std::string, double>> seam_metrics;
};

// JSON report: converged, status, iterations, load steps, final load factor and residual,
// residual history, contact reactions (per vertex and totals per surface and overall), wall
// time, the draped bounding box, plus the context.
std::string drapeReportJson(const DrapeResult& result, const ReportContext& context);

// Writes drapeReportJson to path; throws InputError if it cannot.
void writeDrapeReport(const std::string& path, const DrapeResult& result,
                      const ReportContext& context);

}  // namespace chs
