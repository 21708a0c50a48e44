#pragma once
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"
#include "cloth_hair_sim/core/io/simulation_scene.h"
#include "cloth_hair_sim/core/simulation/simulation_run.h"

namespace chs {

// Pictures of a simulate run, drawn by gnuplot (see runGnuplot); throw std::runtime_error on
// failure.

// One frame as PNG: a shaded 3D view and a front view (x-z) of the bodies' display surfaces
// and the hair's strands (as lines), one colour per body (names: bodies, then hair), and the
// colliders at their poses in grey.
void plotSimulationFrame(const std::vector<DisplaySurface>& bodies,
                         const std::vector<rod::Polylines>& hair,
                         const std::vector<std::string>& body_names,
                         const std::vector<SimulationCollider>& colliders,
                         const std::vector<Eigen::Isometry3d>& collider_poses,
                         const std::string& png_path, const std::string& title);

// Kinetic energy per frame, of the whole world and of each body (names as the records' bodies).
void plotEnergy(const std::vector<FrameRecord>& frames, const std::vector<std::string>& body_names,
                const std::string& png_path, const std::string& title);

// Wall time per frame [ms] and substeps per frame (second axis).
void plotTiming(const std::vector<FrameRecord>& frames, const std::string& png_path,
                const std::string& title);

}  // namespace chs
