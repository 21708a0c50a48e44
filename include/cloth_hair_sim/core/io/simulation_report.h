#pragma once
#include <string>
#include <vector>

#include "cloth_hair_sim/core/io/simulation_scene.h"
#include "cloth_hair_sim/core/simulation/simulation_run.h"

namespace chs {

// How a simulate run went, for its report.
struct SimulationSummary {
  std::vector<FrameRecord> frames;  // frame 0 (the initial state) and every frame completed
  bool completed = true;
  std::string stop_reason;       // why it stopped early ("" if completed)
  double stop_time = 0.0;        // simulated time of the last good state [s]
  double run_wall_time_s = 0.0;  // the whole run, writing the outputs included
  std::string mesh_format;       // obj | ply
  std::vector<std::string> notes;
};

// The JSON report: the scene (bodies, colliders, world settings), per frame the simulated and
// wall time, substeps, rollbacks, kinetic energy, and per body kinetic energy, deepest
// penetration and largest stretch, per collider the mean force and moment; totals (simulated
// time, stepping wall time, real-time factor = simulated / stepping wall time, substeps);
// status and, for a run that stopped, where and why. Non-finite numbers become null.
std::string simulationReportJson(const SimulationScene& scene, const SimulationSummary& summary);
// Throws InputError if the file cannot be written.
void writeSimulationReport(const std::string& path, const SimulationScene& scene,
                           const SimulationSummary& summary);

}  // namespace chs
