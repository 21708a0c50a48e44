#pragma once
// A garment sewn from several flat panels (drape scenes, io/scene.h): the panels' meshes placed
// in the world and joined into one mesh, and the seams between their boundaries resolved to
// pairs of vertices of that mesh. Private to the core, as scene_yaml.h.
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

struct GarmentPanel {
  std::string name;
  int first_vertex = 0;  // its vertices in the joined mesh: first_vertex, first_vertex + 1, ...
  QuadMesh mesh;         // in its own frame, before the pose
  int nx = 0, ny = 0;    // a rectangle's cells (0 for a file panel: no named sides)
};

struct GarmentPanels {
  QuadMesh mesh;  // all panels, posed, in the order given
  std::vector<GarmentPanel> panels;
};

// garment: {panels: [{name, rectangle: {size, cells} | file: path | {path, scale}, position,
// rpy | quaternion}, ...], flat_tolerance: t}. Throws InputError naming the key: duplicate or
// missing names, a panel whose vertices lie off their best-fit plane by more than t (default
// 1e-4 of its bounding-box diagonal).
GarmentPanels parsePanels(const YAML::Node& garment, const std::string& base_dir);

// seams: [{a: {panel, side: left|right|bottom|top | vertices: [..]}, b: {...}, reverse}, ...]
// (vertex indices of the panel's own mesh). Throws InputError for an unknown panel or side, a
// vertex off the panel's boundary, sides of unequal vertex count or of lengths differing by more
// than 1%.
std::vector<Seam> parseSeams(const YAML::Node& seams, const GarmentPanels& panels);

}  // namespace chs
