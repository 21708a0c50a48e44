#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/subdiv/surface_stencil.h"

namespace chs {

// The basis weights N_p and first derivatives of many limit-surface points, in one flat array
// with each point's terms side by side. The contact particles (type iii) need only these, three
// times a step (tangents for the forces and the Coulomb return, positions (5.54)); read from
// SurfaceStencil's seven separate arrays per point, second derivatives included, those passes
// waited on memory and took a fifth of a curtain step.
class FirstOrderStencils {
 public:
  struct Term {
    int point;         // control point index
    double w, du, dv;  // N_p and its (u, v) derivatives
  };

  FirstOrderStencils() = default;
  explicit FirstOrderStencils(const std::vector<SurfaceStencil>& stencils);

  int size() const { return static_cast<int>(begin_.size()) - 1; }
  const Term* begin(int i) const { return terms_.data() + begin_[i]; }
  const Term* end(int i) const { return terms_.data() + begin_[i + 1]; }

  // x(u, v) = sum_p N_p x_p of point i over control positions (or velocities) x.
  Eigen::Vector3d position(int i, const std::vector<Eigen::Vector3d>& x) const {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (const Term* t = begin(i); t != end(i); ++t) s += t->w * x[t->point];
    return s;
  }
  // The tangents a1 = x_u, a2 = x_v of point i.
  void tangents(int i, const std::vector<Eigen::Vector3d>& x, Eigen::Vector3d& a1,
                Eigen::Vector3d& a2) const {
    a1.setZero();
    a2.setZero();
    for (const Term* t = begin(i); t != end(i); ++t) {
      const Eigen::Vector3d& xp = x[t->point];
      a1 += t->du * xp;
      a2 += t->dv * xp;
    }
  }

 private:
  std::vector<int> begin_{0};  // terms of point i: [begin_[i], begin_[i + 1])
  std::vector<Term> terms_;
};

}  // namespace chs
