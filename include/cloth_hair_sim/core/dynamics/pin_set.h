#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/io/state_stream.h"

namespace chs {

// The vertices a dynamics backend holds on a prescribed motion, and where each is held: a
// pinned vertex is carried to its target over the next step, an unpinned one moves freely (its
// last target is kept but unused). Both backends (particle network, hybrid shell) keep their
// pins here, so they check indices and targets with the same rules.
class PinSet {
 public:
  // How error messages name the backend and its vertices, e.g. {"hybrid shell",
  // "control point", "control points"}.
  struct Names {
    std::string backend, vertex, vertices;
  };

  // Nothing pinned; each vertex's target starts at its position.
  PinSet(Names names, std::vector<Eigen::Vector3d> positions);

  int size() const { return static_cast<int>(pinned_.size()); }
  // Throws InputError "<backend>: <vertex> i out of range (n <vertices>)".
  void check(int vertex) const;
  // A holding-force request: accelerations empty or one per vertex, every vertex in range.
  // Throws InputError otherwise.
  void checkHoldingRequest(const std::vector<int>& vertices,
                           const std::vector<Eigen::Vector3d>& accelerations) const;

  // Holds the vertex where `positions` has it now.
  void pinInPlace(int vertex, const std::vector<Eigen::Vector3d>& positions);
  // Holds the vertex at (or carries it to) target; throws InputError for a non-finite target.
  void pin(int vertex, const Eigen::Vector3d& target);
  void unpin(int vertex);
  bool isPinned(int vertex) const { return pinned_.at(vertex) != 0; }
  const Eigen::Vector3d& target(int vertex) const { return targets_[vertex]; }

  // The pinned vertices and their targets, as records of a state file. read() refuses a record
  // of another size or with an index out of range or a non-finite target (InputError), leaving
  // the set as it was.
  void write(StateWriter& out) const;
  void read(StateReader& in);

  // Calls f(vertex) for each pinned vertex in increasing order.
  template <class F>
  void forEachPinned(F&& f) const {
    for (int v = 0; v < size(); ++v)
      if (pinned_[v]) f(v);
  }

 private:
  Names names_;
  std::vector<char> pinned_;
  std::vector<Eigen::Vector3d> targets_;
};

}  // namespace chs
