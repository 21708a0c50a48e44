#include "cloth_hair_sim/core/io/mesh_writer.h"

#include <array>
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

// Vertices and faces of N corners each, kept as they are (quads stay quads).
template <std::size_t N>
void objFile(const std::string& path, const std::string& what,
             const std::vector<Eigen::Vector3d>& positions,
             const std::vector<std::array<int, N>>& faces) {
  std::ofstream out = open(path);
  out << "# cloth_hair_sim " << what << ": " << positions.size() << " vertices, " << faces.size()
      << " faces\n";
  for (const auto& p : positions) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& f : faces) {  // OBJ indices are 1-based; -1 ends a shorter face
    out << 'f';
    for (int v : f)
      if (v >= 0) out << ' ' << v + 1;
    out << '\n';
  }
  finish(out, path);
}

template <std::size_t N>
void plyFile(const std::string& path, const std::string& what,
             const std::vector<Eigen::Vector3d>& positions,
             const std::vector<std::array<int, N>>& faces) {
  std::ofstream out = open(path);
  out << "ply\nformat ascii 1.0\ncomment cloth_hair_sim " << what << "\n"
      << "element vertex " << positions.size() << "\nproperty double x\nproperty double y\n"
      << "property double z\nelement face " << faces.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : positions) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& f : faces) {
    out << N;
    for (int v : f) out << ' ' << v;
    out << '\n';
  }
  finish(out, path);
}

void checkPositions(const std::string& path, const QuadMesh& mesh,
                    const std::vector<Eigen::Vector3d>& positions) {
  if (positions.size() != mesh.vertices.size())
    throw InputError(path + ": " + std::to_string(positions.size()) + " positions for a mesh of " +
                     std::to_string(mesh.vertices.size()) + " vertices");
}

}  // namespace

void writeObj(const std::string& path, const QuadMesh& mesh,
              const std::vector<Eigen::Vector3d>& positions) {
  checkPositions(path, mesh, positions);
  objFile(path, "quad mesh", positions, mesh.quads);
}

void writeElementsObj(const std::string& path, const std::vector<Eigen::Vector3d>& positions,
                      const std::vector<std::array<int, 4>>& elements) {
  for (const auto& e : elements)
    for (int v : e)
      if (v >= static_cast<int>(positions.size()))
        throw InputError(path + ": an element refers to vertex " + std::to_string(v) + " of " +
                         std::to_string(positions.size()));
  objFile(path, "element mesh", positions, elements);
}

void writePly(const std::string& path, const QuadMesh& mesh,
              const std::vector<Eigen::Vector3d>& positions) {
  checkPositions(path, mesh, positions);
  plyFile(path, "quad mesh", positions, mesh.quads);
}

void writeSurfaceObj(const std::string& path, const DisplaySurface& surface) {
  objFile(path, "display surface", surface.vertices, surface.triangles);
}

void writeSurfacePly(const std::string& path, const DisplaySurface& surface) {
  plyFile(path, "display surface", surface.vertices, surface.triangles);
}

void writeStrandsObj(const std::string& path, const rod::Polylines& strands) {
  std::ofstream out = open(path);
  out << "# cloth_hair_sim strands\n";
  for (const auto& strand : strands)
    for (const auto& p : strand) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  long first = 1;  // OBJ indices are 1-based
  for (const auto& strand : strands) {
    out << 'l';
    for (std::size_t i = 0; i < strand.size(); ++i) out << ' ' << first + static_cast<long>(i);
    out << '\n';
    first += static_cast<long>(strand.size());
  }
  finish(out, path);
}

void writeStrandsPly(const std::string& path, const rod::Polylines& strands) {
  long vertices = 0, edges = 0;
  for (const auto& strand : strands) {
    vertices += static_cast<long>(strand.size());
    edges += static_cast<long>(strand.size()) - 1;
  }
  std::ofstream out = open(path);
  out << "ply\nformat ascii 1.0\ncomment cloth_hair_sim strands\n"
      << "element vertex " << vertices << "\nproperty double x\nproperty double y\n"
      << "property double z\nelement edge " << edges
      << "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  for (const auto& strand : strands)
    for (const auto& p : strand) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  long first = 0;
  for (const auto& strand : strands) {
    for (std::size_t i = 1; i < strand.size(); ++i)
      out << first + static_cast<long>(i) - 1 << ' ' << first + static_cast<long>(i) << '\n';
    first += static_cast<long>(strand.size());
  }
  finish(out, path);
}

}  // namespace chs
