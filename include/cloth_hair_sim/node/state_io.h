#pragma once
#include <cstdint>
#include <map>
#include <string>

#include "cloth_hair_sim/node/garment.h"
#include "cloth_hair_sim/node/grasp.h"
#include "cloth_hair_sim/node/hair.h"
#include "cloth_hair_sim/node/sim_params.h"

namespace chs_node {

// The node's clock and counters that a saved simulation carries.
struct SimClock {
  double sim_time = 0.0;
  std::uint64_t steps = 0;
  bool paused = false;
  int rollbacks = 0;
  int unconverged_solves = 0;
};

// A simulation read back from a state file, rebuilt and checked, ready to replace the running
// one. The grasps' wrench publishers are not advertised; the garments have no colliders yet.
struct SavedSimulation {
  SimClock clock;
  std::map<std::string, Garment> garments;
  std::map<std::string, Grasp> grasps;
  std::map<std::string, Hair> hairs;  // bodies on their saved grid spacing, no colliders yet
  std::map<std::string, HairGrasp> hair_grasps;
};

// The payload of a state file (core io/state_file.h): each garment as the LoadGarment request
// and the frame poses it was built with, its reference mesh, its frame pins' poses and its
// backend's state; each grasp with its attachment and wrench history; each hair as its
// LoadHair request, root frame poses, grid and its body's state (HairDynamics::writeState), and
// each grasp of hair; the clock.
std::string encodeSimulation(const std::string& backend, const SimClock& clock,
                             const std::map<std::string, Garment>& garments,
                             const std::map<std::string, Grasp>& grasps,
                             const std::map<std::string, Hair>& hairs,
                             const std::map<std::string, HairGrasp>& hair_grasps);

// Reads a state file and rebuilds its garments with `params`, whose backend must be the saved
// one (its other settings are this node's), and its hair with `hair` (this node's hair
// settings; the grid spacing is the saved one) and display_default display strands. Throws
// chs::InputError "<path>: ..." naming the problem: not a state file, another format version,
// corruption or truncation, a LoadGarment or LoadHair definition of another build, a garment or
// hair that cannot be rebuilt or whose mesh or strands changed since.
SavedSimulation readSimulation(const std::string& path, const SimParams& params,
                               const chs::rod::HairSettings& hair, int display_default);

}  // namespace chs_node
