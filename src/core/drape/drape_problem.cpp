#include "cloth_hair_sim/core/drape/drape_problem.h"

#include <string>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/drape/seam_groups.h"
#include "cloth_hair_sim/core/mesh/mesh_check.h"
#include "cloth_hair_sim/core/mesh/scene_scale.h"

namespace chs {

void DrapeProblem::validate() const {
  material.validate();
  if (fabric) fabric->validate();
  checkMesh(mesh);
  checkSceneScale(mesh);
  if (!gravity.allFinite()) throw InputError("gravity must be finite");
  const int n = mesh.numVertices();
  auto checkIndex = [n](int v, const char* what) {
    if (v < 0 || v >= n)
      throw InputError(std::string(what) + " names vertex " + std::to_string(v) +
                       ", but the mesh has " + std::to_string(n) + " vertices");
  };
  for (int v : bc.clamped) checkIndex(v, "clamped list");
  for (int v : bc.pinned) checkIndex(v, "pinned list");
  for (const auto& f : bc.fixed_components) {
    checkIndex(f.vertex, "fixed component");
    if (f.axis < 0 || f.axis > 2) throw InputError("fixed component axis must be 0, 1 or 2");
  }
  for (const auto& l : bc.loads) {
    checkIndex(l.vertex, "nodal load");
    if (!l.force.allFinite() || !l.moment.allFinite())
      throw InputError("nodal load on vertex " + std::to_string(l.vertex) + " is not finite");
  }
  if (!seams.empty()) SeamGroups(n, seams);  // throws for unequal sides, bad or self-sewn vertices
  for (std::size_t i = 0; i < colliders.size(); ++i)
    if (!colliders[i]) throw InputError("collider " + std::to_string(i) + " is empty");
}

void DrapeProblem::checkStaticSupport() const {
  if (bc.clamped.empty() && bc.pinned.empty() && bc.fixed_components.empty() && colliders.empty())
    throw InputError(
        "no support at all: nothing is clamped, pinned or fixed and there are no colliders, so "
        "the garment has rigid-body modes");
}

}  // namespace chs
