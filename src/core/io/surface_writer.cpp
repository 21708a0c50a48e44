#include "cloth_hair_sim/core/io/surface_writer.h"

#include <fstream>
#include <iomanip>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace {

std::ofstream open(const std::string& path) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot open for writing");
  out << std::setprecision(10);
  return out;
}

void finish(std::ofstream& out, const std::string& path) {
  out.close();
  if (!out) throw InputError(path + ": write failed");
}

}  // namespace

void writeSurfaceObj(const std::string& path, const DisplaySurface& surface) {
  std::ofstream out = open(path);
  out << "# cloth_hair_sim display surface: " << surface.vertices.size() << " vertices, "
      << surface.triangles.size() << " triangles\n";
  for (const auto& p : surface.vertices)
    out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& t : surface.triangles)  // OBJ indices are 1-based
    out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  finish(out, path);
}

void writeSurfacePly(const std::string& path, const DisplaySurface& surface) {
  std::ofstream out = open(path);
  out << "ply\nformat ascii 1.0\ncomment cloth_hair_sim display surface\n"
      << "element vertex " << surface.vertices.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nelement face "
      << surface.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : surface.vertices) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& t : surface.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  finish(out, path);
}

}  // namespace chs
