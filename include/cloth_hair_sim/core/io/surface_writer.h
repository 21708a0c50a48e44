#pragma once
#include <string>

#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"

namespace chs {

// A dynamics backend's display surface (triangles) as OBJ or ASCII PLY, one file per frame of a
// sequence. Throws InputError if the file cannot be written.
void writeSurfaceObj(const std::string& path, const DisplaySurface& surface);
void writeSurfacePly(const std::string& path, const DisplaySurface& surface);

}  // namespace chs
