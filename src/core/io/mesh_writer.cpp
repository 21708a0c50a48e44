#include "cloth_hair_sim/core/io/mesh_writer.h"

#include <fstream>
#include <iomanip>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace {

std::ofstream openFor(const std::string& path, const QuadMesh& mesh,
                      const std::vector<Eigen::Vector3d>& positions) {
  if (positions.size() != mesh.vertices.size())
    throw InputError(path + ": " + std::to_string(positions.size()) + " positions for a mesh of " +
                     std::to_string(mesh.vertices.size()) + " vertices");
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

void writeObj(const std::string& path, const QuadMesh& mesh,
              const std::vector<Eigen::Vector3d>& positions) {
  std::ofstream out = openFor(path, mesh, positions);
  out << "# cloth_hair_sim quad mesh: " << positions.size() << " vertices, " << mesh.numQuads()
      << " quads\n";
  for (const auto& p : positions) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& q : mesh.quads)  // OBJ indices are 1-based
    out << "f " << q[0] + 1 << ' ' << q[1] + 1 << ' ' << q[2] + 1 << ' ' << q[3] + 1 << '\n';
  finish(out, path);
}

void writePly(const std::string& path, const QuadMesh& mesh,
              const std::vector<Eigen::Vector3d>& positions) {
  std::ofstream out = openFor(path, mesh, positions);
  out << "ply\nformat ascii 1.0\ncomment cloth_hair_sim quad mesh\n"
      << "element vertex " << positions.size() << "\nproperty double x\nproperty double y\n"
      << "property double z\nelement face " << mesh.numQuads()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : positions) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& q : mesh.quads)
    out << "4 " << q[0] << ' ' << q[1] << ' ' << q[2] << ' ' << q[3] << '\n';
  finish(out, path);
}

}  // namespace chs
