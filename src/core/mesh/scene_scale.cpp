#include "cloth_hair_sim/core/mesh/scene_scale.h"

#include <sstream>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

void checkSceneScale(const QuadMesh& mesh) {
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double far = mesh.vertices[v].cwiseAbs().maxCoeff();
    if (far > kMaxSceneCoordinate) {
      std::ostringstream s;
      s << "mesh: vertex " << v << " lies at (" << mesh.vertices[v].transpose() << ") m, "
        << far / 1000.0 << " km from the world origin; a robot scene holds nothing beyond "
        << kMaxSceneCoordinate / 1000.0 << " km (a wrong scale or pose?)";
      throw InputError(s.str());
    }
  }
  for (int q = 0; q < mesh.numQuads(); ++q)
    for (int k = 0; k < 4; ++k) {
      const int a = mesh.quads[q][k], b = mesh.quads[q][(k + 1) % 4];
      const double length = (mesh.vertices[a] - mesh.vertices[b]).norm();
      if (length < kMinCellEdge) {
        std::ostringstream s;
        s << "mesh: edge " << a << "-" << b << " of quad " << q << " is " << length * 1e3
          << " mm long, below the " << kMinCellEdge * 1e3
          << " mm that a cell may be (a wrong scale, or vertices to weld?)";
        throw InputError(s.str());
      }
    }
}

}  // namespace chs
