#include "cloth_hair_sim/core/mpm/time_integration.h"

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

std::string timeIntegrationName(TimeIntegration integration) {
  switch (integration) {
    case TimeIntegration::kSymplecticEuler:
      return "symplectic_euler";
    case TimeIntegration::kBackwardEuler:
      return "backward_euler";
    case TimeIntegration::kLagrangianImplicit:
      return "lagrangian_implicit";
    case TimeIntegration::kLagrangianBdf2:
      return "lagrangian_bdf2";
  }
  return "unknown";
}

TimeIntegration timeIntegrationFromName(const std::string& name) {
  for (TimeIntegration i : {TimeIntegration::kSymplecticEuler, TimeIntegration::kBackwardEuler,
                            TimeIntegration::kLagrangianImplicit, TimeIntegration::kLagrangianBdf2})
    if (name == timeIntegrationName(i)) return i;
  throw InputError("integration '" + name +
                   "': must be symplectic_euler, backward_euler, lagrangian_implicit or "
                   "lagrangian_bdf2");
}

}  // namespace chs
