#include "cloth_hair_sim/core/subdiv/first_order_stencils.h"

namespace chs {

FirstOrderStencils::FirstOrderStencils(const std::vector<SurfaceStencil>& stencils) {
  std::size_t total = 0;
  for (const SurfaceStencil& s : stencils) total += s.points.size();
  terms_.reserve(total);
  begin_.reserve(stencils.size() + 1);
  for (const SurfaceStencil& s : stencils) {
    for (int k = 0; k < s.size(); ++k) terms_.push_back({s.points[k], s.w[k], s.du[k], s.dv[k]});
    begin_.push_back(static_cast<int>(terms_.size()));
  }
}

}  // namespace chs
