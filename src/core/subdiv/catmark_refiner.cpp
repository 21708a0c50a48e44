#include "catmark_refiner.h"

#include <set>
#include <string>
#include <utility>

#include <opensubdiv/far/topologyDescriptor.h>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

namespace {

std::string edgeName(int a, int b) {
  return "edge " + std::to_string(a) + "-" + std::to_string(b);
}

// Topology checks OpenSubdiv would otherwise accept silently (it tags non-manifold features
// and carries on) but that leave the shell without a well-defined normal side.
void checkFaces(int num_vertices, const std::vector<int>& face_sizes,
                const std::vector<int>& face_vertices) {
  const int nf = static_cast<int>(face_sizes.size());
  if (num_vertices <= 0 || nf == 0)
    throw InputError("subdivision mesh is empty: " + std::to_string(num_vertices) + " vertices, " +
                     std::to_string(nf) + " faces");

  std::vector<char> used(num_vertices, 0);
  // Directed edges (a, b) run so far. A third face on an edge necessarily repeats a
  // direction, so this one set catches flipped faces and non-manifold edges alike.
  std::set<std::pair<int, int>> directed;
  int offset = 0;
  for (int f = 0; f < nf; ++f) {
    const int n = face_sizes[f];
    if (n < 3)
      throw InputError("subdivision mesh: face " + std::to_string(f) + " has " + std::to_string(n) +
                       " corners, at least 3 needed");
    const int* c = face_vertices.data() + offset;
    for (int k = 0; k < n; ++k) {
      if (c[k] < 0 || c[k] >= num_vertices)
        throw InputError("subdivision mesh: face " + std::to_string(f) + " names vertex " +
                         std::to_string(c[k]) + ", but the mesh has " +
                         std::to_string(num_vertices) + " vertices");
      for (int l = 0; l < k; ++l)
        if (c[l] == c[k])
          throw InputError("subdivision mesh: face " + std::to_string(f) + " repeats vertex " +
                           std::to_string(c[k]));
      used[c[k]] = 1;
    }
    for (int k = 0; k < n; ++k) {
      const int a = c[k], b = c[(k + 1) % n];
      if (!directed.insert({a, b}).second)
        throw InputError("subdivision mesh: " + edgeName(a, b) +
                         " is run in the same direction by two faces (the second is face " +
                         std::to_string(f) +
                         "): inconsistent orientation or an edge of more than two faces");
    }
    offset += n;
  }
  for (int v = 0; v < num_vertices; ++v)
    if (!used[v])
      throw InputError("subdivision mesh: vertex " + std::to_string(v) + " belongs to no face");
}

}  // namespace

std::unique_ptr<Far::TopologyRefiner> makeCatmarkRefiner(int num_vertices,
                                                         const std::vector<int>& face_sizes,
                                                         const std::vector<int>& face_vertices) {
  checkFaces(num_vertices, face_sizes, face_vertices);

  Far::TopologyDescriptor desc;
  desc.numVertices = num_vertices;
  desc.numFaces = static_cast<int>(face_sizes.size());
  desc.numVertsPerFace = face_sizes.data();
  desc.vertIndicesPerFace = face_vertices.data();

  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
  if (!refiner) throw InputError("subdivision mesh: OpenSubdiv rejected the topology");

  // Edges passed the checks above; what is left is a vertex joining separate fans of faces
  // (a "bow tie"), around which no single tangent plane exists.
  const Far::TopologyLevel& level = refiner->GetLevel(0);
  for (int v = 0; v < num_vertices; ++v)
    if (level.IsVertexNonManifold(v))
      throw InputError("subdivision mesh: vertex " + std::to_string(v) +
                       " is non-manifold (its faces form more than one fan)");
  return refiner;
}

}  // namespace chs
