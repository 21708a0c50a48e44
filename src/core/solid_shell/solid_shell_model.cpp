#include "cloth_hair_sim/core/solid_shell/solid_shell_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/solver/storage_slot.h"

namespace chs {

SolidShellRigidity isotropicRigidity(const ShellMaterial& m) {
  SolidShellRigidity c;
  Eigen::Matrix3d plane;
  plane << 1, m.poisson, 0, m.poisson, 1, 0, 0, 0, 0.5 * (1 - m.poisson);
  c.membrane = m.membraneStiffness() * plane;
  c.bending = m.bendingStiffness() * plane;
  c.shear = m.shear_correction * m.shearModulus() * m.thickness * Eigen::Matrix2d::Identity();
  c.thickness = m.young * m.thickness;
  return c;
}

SolidShellMesh solidShellMesh(const DrapeProblem& problem) {
  const QuadMesh& mesh = problem.mesh;
  const int nv = mesh.numVertices();
  // Reference directors: area-weighted vertex normals of the flat mesh, unit length (X_n of
  // eq. (1) is normalised).
  std::vector<Eigen::Vector3d> normal(nv, Eigen::Vector3d::Zero());
  for (const auto& q : mesh.quads) {
    const Eigen::Vector3d c = (mesh.vertices[q[2]] - mesh.vertices[q[0]])
                                  .cross(mesh.vertices[q[3]] - mesh.vertices[q[1]]);
    for (int v : q) normal[v] += c;
  }
  SolidShellMesh m;
  m.X = mesh.vertices;
  m.Xn.resize(nv);
  for (int v = 0; v < nv; ++v) m.Xn[v] = normal[v].normalized();
  m.elements = mesh.quads;
  m.bc = problem.bc;
  return m;
}

SolidShellModel::SolidShellModel(const DrapeProblem& problem, ThicknessStrain thickness_strain,
                                 double mu, double contact_stiffness, bool centred_band)
    : SolidShellModel(problem, solidShellMesh(problem), thickness_strain, mu, contact_stiffness,
                      centred_band) {}

SolidShellModel::SolidShellModel(const DrapeProblem& problem, SolidShellMesh mesh,
                                 ThicknessStrain thickness_strain, double mu,
                                 double contact_stiffness, bool centred_band)
    : problem_(problem), centred_band_(centred_band) {
  if (problem.material.kawabata)
    throw InputError(
        "solid_shell: the Kawabata bending law is not supported (linear bending only)");
  for (const auto& l : mesh.bc.loads)
    if (l.moment.norm() > 0.0)
      throw InputError("solid_shell: nodal moments are not supported (vertex " +
                       std::to_string(l.vertex) + "); give forces");
  const int nv = static_cast<int>(mesh.X.size());
  X_ = std::move(mesh.X);
  Xn_ = std::move(mesh.Xn);
  u_.assign(nv, Eigen::Vector3d::Zero());
  un_.assign(nv, Eigen::Vector3d::Zero());
  active_.assign(nv, false);
  for (const auto& q : mesh.elements)
    for (int v : q)
      if (v >= 0) active_[v] = true;

  const bool woven = problem.fabric.has_value();
  const SolidShellRigidity rigidity = [&] {
    if (!woven) return isotropicRigidity(problem.material);
    SolidShellRigidity c;
    c.membrane = problem.fabric->membraneRigidity();
    c.bending = problem.fabric->bendingRigidity();
    c.shear = problem.fabric->transverseShearRigidity() * Eigen::Matrix2d::Identity();
    c.thickness = problem.fabric->thicknessRigidity();
    return c;
  }();
  const double density = woven ? problem.fabric->areal_density : problem.material.areal_density;
  const double h = woven ? problem.fabric->thickness : problem.material.thickness;
  std::vector<double> nodal_mass(nv, 0.0);
  elements_.reserve(mesh.elements.size());
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    const auto& q = mesh.elements[e];
    const int corners = q[3] < 0 ? 3 : 4;
    std::array<Eigen::Vector3d, 4> X, Xn;
    for (int i = 0; i < corners; ++i) X[i] = X_[q[i]], Xn[i] = Xn_[q[i]];
    const Eigen::Vector3d axis = woven ? problem.fabric->warp : Eigen::Vector3d(X[1] - X[0]);
    if (corners == 4)
      elements_.emplace_back(q, X, Xn, axis, rigidity, thickness_strain, mu);
    else
      elements_.emplace_back(std::array<int, 3>{q[0], q[1], q[2]},
                             std::array<Eigen::Vector3d, 3>{X[0], X[1], X[2]},
                             std::array<Eigen::Vector3d, 3>{Xn[0], Xn[1], Xn[2]}, axis, rigidity,
                             thickness_strain, mu);
    if (!elements_.back().isValid())
      throw InputError((corners == 4 ? "quad " : "triangle ") + std::to_string(e) +
                       (woven ? " is degenerate, folded over or normal to the warp direction"
                              : " is degenerate or folded over"));
    for (int i = 0; i < corners; ++i)
      nodal_mass[q[i]] += density * elements_.back().nodalAreas()[i];
  }
  weight_.resize(nv);
  for (int v = 0; v < nv; ++v) weight_[v] = nodal_mass[v] * problem.gravity;
  for (const auto& l : mesh.bc.loads) weight_[l.vertex] += l.force;

  dof_.assign(6 * nv, 0);
  for (int v = 0; v < nv; ++v)
    if (!active_[v])
      for (int k = 0; k < 6; ++k) dof_[6 * v + k] = -1;
  for (int v : mesh.bc.clamped)
    for (int k = 0; k < 6; ++k) dof_[6 * v + k] = -1;
  for (int v : mesh.bc.pinned)
    for (int k = 0; k < 3; ++k) dof_[6 * v + k] = -1;
  for (const auto& f : mesh.bc.fixed_components) dof_[6 * f.vertex + f.axis] = -1;
  for (int& d : dof_)
    if (d == 0) d = num_free_++;
  mass_.setZero(num_free_);
  translation_.assign(num_free_, false);
  double load2 = 0.0;
  for (int v = 0; v < nv; ++v) {
    for (int k = 0; k < 6; ++k)
      if (dof_[6 * v + k] >= 0) {
        mass_[dof_[6 * v + k]] = nodal_mass[v] * (k < 3 ? 1.0 : h * h / 4);
        translation_[dof_[6 * v + k]] = k < 3;
      }
    load2 += weight_[v].squaredNorm();
  }
  load_norm_ = std::sqrt(load2);
  Eigen::AlignedBox3d box;
  for (const auto& x : X_) box.extend(x);
  length_scale_ = std::max(box.diagonal().norm(), 1e-12);
  double edges = 0.0;
  int num_edges = 0;
  for (const auto& el : elements_)
    for (int i = 0; i < el.corners(); ++i, ++num_edges)
      edges += (X_[el.nodes()[i]] - X_[el.nodes()[(i + 1) % el.corners()]]).norm();
  smoothing_ = 1e-4 * (num_edges == 0 ? 1.0 : edges / num_edges);
  // As the FEM shell: a hundred times the (largest) membrane rigidity.
  k_contact_ =
      contact_stiffness > 0.0 ? contact_stiffness : 100.0 * rigidity.membrane.diagonal().maxCoeff();

  // Sparsity: element blocks and the nodal x_o blocks.
  std::vector<Eigen::Triplet<double>> trip;
  auto free = [&](int v, int k) { return dof_[6 * v + k]; };
  for (const auto& el : elements_)
    for (int a = 0; a < 6 * el.corners(); ++a)
      for (int b = 0; b < 6 * el.corners(); ++b) {
        const int r = free(el.nodes()[a / 6], a % 6), c = free(el.nodes()[b / 6], b % 6);
        if (r >= 0 && c >= 0) trip.emplace_back(r, c, 0.0);
      }
  pattern_.resize(num_free_, num_free_);
  pattern_.setFromTriplets(trip.begin(), trip.end());
  pattern_.makeCompressed();
  auto slot = [&](int r, int c) { return storageSlot(pattern_, r, c); };
  slots_.resize(elements_.size());
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const auto& q = elements_[e].nodes();
    slots_[e].fill(-1);
    const int n = 6 * elements_[e].corners();
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        slots_[e][a * 24 + b] = slot(free(q[a / 6], a % 6), free(q[b / 6], b % 6));
  }
  node_slots_.resize(nv);
  for (int v = 0; v < nv; ++v)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) node_slots_[v][a * 3 + b] = slot(free(v, a), free(v, b));
  fe_.resize(elements_.size());
  ue_.resize(elements_.size());
}

SolidShellState SolidShellModel::elementState(int e) const {
  const auto& q = elements_[e].nodes();
  SolidShellState s;
  for (int i = 0; i < 4; ++i) s[2 * i] = s[2 * i + 1] = Eigen::Vector3d::Zero();
  for (int i = 0; i < elements_[e].corners(); ++i) s[2 * i] = u_[q[i]], s[2 * i + 1] = un_[q[i]];
  return s;
}

double SolidShellModel::assemble(Eigen::VectorXd& R, Eigen::SparseMatrix<double>* K) {
  if (K) Ke_.resize(elements_.size());
  tbb::parallel_for(std::size_t(0), elements_.size(), [&](std::size_t e) {
    ue_[e] =
        elements_[e].evaluate(elementState(static_cast<int>(e)), &fe_[e], K ? &Ke_[e] : nullptr);
  });
  R.setZero(num_free_);
  double* kv = nullptr;
  if (K) {
    if (K->nonZeros() != pattern_.nonZeros() || K->rows() != num_free_) *K = pattern_;
    kv = K->valuePtr();
    std::fill(kv, kv + K->nonZeros(), 0.0);
  }
  double energy = 0.0;
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    energy += ue_[e];
    const auto& q = elements_[e].nodes();
    for (int a = 0; a < 6 * elements_[e].corners(); ++a) {
      const int r = dof_[6 * q[a / 6] + a % 6];
      if (r >= 0) R[r] -= fe_[e][a];
    }
    if (!K) continue;
    for (int ab = 0; ab < 576; ++ab)
      if (slots_[e][ab] >= 0) kv[slots_[e][ab]] += Ke_[e](ab / 24, ab % 24);
  }
  active_contacts_ = 0;
  for (std::size_t v = 0; v < X_.size(); ++v) {
    if (!active_[v]) continue;
    Eigen::Vector3d f = weight_[v];
    Eigen::Matrix3d k = Eigen::Matrix3d::Zero();
    for (const auto& surface : problem_.colliders) {
      const SurfaceProjection p = surface->project(X_[v] + u_[v]);
      const Penalty c = penalty(p.gap);
      if (c.stiffness == 0.0) continue;
      ++active_contacts_;
      f += c.force * p.normal;
      k += c.stiffness * p.normal * p.normal.transpose() - c.force * p.normal_gradient;
    }
    for (int a = 0; a < 3; ++a) {
      const int r = dof_[6 * v + a];
      if (r < 0) continue;
      R[r] += f[a];
      if (!K) continue;
      for (int b = 0; b < 3; ++b)
        if (node_slots_[v][a * 3 + b] >= 0) kv[node_slots_[v][a * 3 + b]] += k(a, b);
    }
  }
  return energy;
}

SolidShellModel::Penalty SolidShellModel::penalty(double gap) const {
  // The FEM shell's penalty: k_c times the penetration, its kink rounded over a band of width
  // delta, centred on the surface for the static solve (a cloth laid on a table is held from the
  // start) or inside it for dynamics (a cloth laid on a table is not kicked off it).
  const double delta = smoothing_, p = (centred_band_ ? 0.5 * delta : 0.0) - gap;
  if (p <= 0.0) return {0.0, 0.0};
  if (p >= delta) return {k_contact_ * (p - 0.5 * delta), k_contact_};
  return {0.5 * k_contact_ * p * p / delta, k_contact_ * p / delta};
}

double SolidShellModel::penaltyEnergy(double gap) const {
  const double delta = smoothing_, p = (centred_band_ ? 0.5 * delta : 0.0) - gap;
  if (p <= 0.0) return 0.0;
  if (p >= delta) return k_contact_ * (delta * delta / 6.0 + 0.5 * p * (p - delta));
  return k_contact_ * p * p * p / (6.0 * delta);
}

double SolidShellModel::potentialEnergy(double load_factor) const {
  std::vector<double> u(elements_.size());
  tbb::parallel_for(std::size_t(0), elements_.size(), [&](std::size_t e) {
    u[e] = elements_[e].evaluate(elementState(static_cast<int>(e)), nullptr, nullptr);
  });
  double energy = 0.0;
  for (double w : u) energy += w;
  for (std::size_t v = 0; v < X_.size(); ++v) {
    if (!active_[v]) continue;
    energy -= load_factor * weight_[v].dot(u_[v]);
    for (const auto& surface : problem_.colliders)
      energy += penaltyEnergy(surface->project(X_[v] + u_[v]).gap);
  }
  return energy;
}

Eigen::VectorXd SolidShellModel::loadVector() const {
  Eigen::VectorXd P = Eigen::VectorXd::Zero(num_free_);
  for (std::size_t v = 0; v < X_.size(); ++v)
    for (int a = 0; a < 3; ++a)
      if (dof_[6 * v + a] >= 0) P[dof_[6 * v + a]] = weight_[v][a];
  return P;
}

void SolidShellModel::increment(const Eigen::VectorXd& dD) {
  for (std::size_t v = 0; v < X_.size(); ++v)
    for (int k = 0; k < 6; ++k) {
      const int d = dof_[6 * v + k];
      if (d < 0) continue;
      (k < 3 ? u_[v][k] : un_[v][k - 3]) += dD[d];
    }
}

std::pair<double, double> SolidShellModel::largestIncrement(const Eigen::VectorXd& dD) const {
  double move = 0.0, turn = 0.0;
  for (std::size_t v = 0; v < X_.size(); ++v) {
    double t2 = 0.0, n2 = 0.0;
    for (int k = 0; k < 6; ++k) {
      const int d = dof_[6 * v + k];
      if (d >= 0) (k < 3 ? t2 : n2) += dD[d] * dD[d];
    }
    move = std::max(move, t2);
    turn = std::max(turn, n2);
  }
  return {std::sqrt(move), std::sqrt(turn)};
}

Eigen::VectorXd SolidShellModel::freeState() const {
  Eigen::VectorXd D(num_free_);
  for (std::size_t v = 0; v < X_.size(); ++v)
    for (int k = 0; k < 6; ++k)
      if (dof_[6 * v + k] >= 0) D[dof_[6 * v + k]] = k < 3 ? u_[v][k] : un_[v][k - 3];
  return D;
}

void SolidShellModel::setFreeState(const Eigen::VectorXd& D) {
  for (std::size_t v = 0; v < X_.size(); ++v)
    for (int k = 0; k < 6; ++k)
      if (dof_[6 * v + k] >= 0) (k < 3 ? u_[v][k] : un_[v][k - 3]) = D[dof_[6 * v + k]];
}

void SolidShellModel::setDisplacements(const std::vector<Eigen::Vector3d>& u,
                                       const std::vector<Eigen::Vector3d>& un) {
  if (u.size() != u_.size() || un.size() != un_.size())
    throw std::invalid_argument("SolidShellModel::setDisplacements: one value per node");
  u_ = u;
  un_ = un;
}

std::vector<Eigen::Vector3d> SolidShellModel::positions() const {
  std::vector<Eigen::Vector3d> x(X_.size());
  for (std::size_t v = 0; v < X_.size(); ++v) x[v] = X_[v] + u_[v];
  return x;
}

std::vector<Eigen::Vector3d> SolidShellModel::directors() const {
  std::vector<Eigen::Vector3d> n(X_.size());
  for (std::size_t v = 0; v < X_.size(); ++v) n[v] = Xn_[v] + un_[v];
  return n;
}

int SolidShellModel::reversedDirectors() const {
  int count = 0;
  for (std::size_t e = 0; e < elements_.size(); ++e)
    count += elements_[e].reversedDirectors(elementState(static_cast<int>(e)));
  return count;
}

std::vector<ContactReaction> SolidShellModel::reactions() const {
  std::vector<ContactReaction> out;
  for (std::size_t v = 0; v < X_.size(); ++v)
    for (std::size_t s = 0; s < problem_.colliders.size() && active_[v]; ++s) {
      const SurfaceProjection p = problem_.colliders[s]->project(X_[v] + u_[v]);
      const Penalty f = penalty(p.gap);
      if (f.force > 0.0)
        out.push_back({static_cast<int>(v), static_cast<int>(s), f.force * p.normal});
    }
  return out;
}

}  // namespace chs
