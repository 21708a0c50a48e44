#include "cloth_hair_sim/core/fem_shell/shell_model.h"

#include <algorithm>
#include <limits>
#include <random>
#include <tuple>

#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/drape/seam_groups.h"
#include "cloth_hair_sim/core/solver/storage_slot.h"

namespace chs {

namespace {
Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}
}  // namespace

ShellModel::ShellModel(const DrapeProblem& problem, double contact_stiffness, bool edge_contact,
                       bool join_seams)
    : problem_(problem) {
  const QuadMesh& mesh = problem.mesh;
  const int nv = mesh.numVertices();
  // Reference directors t_0: area-weighted vertex normals of the stress-free mesh (eq. (2)).
  std::vector<Eigen::Vector3d> normal(nv, Eigen::Vector3d::Zero());
  for (const auto& q : mesh.quads) {
    const Eigen::Vector3d n = (mesh.vertices[q[2]] - mesh.vertices[q[0]])
                                  .cross(mesh.vertices[q[3]] - mesh.vertices[q[1]]);
    for (int v : q) normal[v] += n;
  }
  nodes_.resize(nv);
  for (int v = 0; v < nv; ++v) {
    nodes_[v].position = mesh.vertices[v];
    nodes_[v].frame = DirectorFrame(normal[v].normalized());
  }
  f_dead_.assign(nv, Eigen::Vector3d::Zero());
  nodal_mass_.assign(nv, 0.0);
  moment_.assign(nv, Eigen::Vector3d::Zero());
  elements_.reserve(mesh.numQuads());
  for (int e = 0; e < mesh.numQuads(); ++e) {
    const auto& q = mesh.quads[e];
    std::array<Eigen::Vector3d, 4> X, T;
    for (int I = 0; I < 4; ++I) X[I] = mesh.vertices[q[I]], T[I] = nodes_[q[I]].frame.director();
    elements_.emplace_back(q, X, T, problem.material);
    if (!elements_.back().isValid())
      throw InputError("quad " + std::to_string(e) + " is degenerate or folded over");
    // Gravity as a distributed load, consistently lumped: int N_I rho g dA.
    for (int I = 0; I < 4; ++I) {
      const double m = elements_.back().nodalAreas()[I] * problem.material.areal_density;
      nodal_mass_[q[I]] += m;
      f_dead_[q[I]] += m * problem.gravity;
    }
  }
  for (const auto& l : problem.bc.loads) {
    f_dead_[l.vertex] += l.force;
    moment_[l.vertex] += l.moment;
  }

  dof_.assign(5 * nv, 0);
  for (int v : problem.bc.clamped)
    for (int k = 0; k < 5; ++k) dof_[5 * v + k] = -1;
  for (int v : problem.bc.pinned)
    for (int k = 0; k < 3; ++k) dof_[5 * v + k] = -1;
  for (const auto& f : problem.bc.fixed_components) dof_[5 * f.vertex + f.axis] = -1;
  // A sewn group's translations are one set of unknowns, numbered at its first member; it is
  // held along an axis if any member is.
  std::vector<int> tied_to(nv, -1);
  if (join_seams && !problem.seams.empty()) {
    seam_groups_ = SeamGroups(nv, problem.seams).groups();
    for (const auto& g : seam_groups_)
      for (int k = 0; k < 3; ++k) {
        bool held = false;
        for (int v : g) held = held || dof_[5 * v + k] < 0;
        for (int v : g) dof_[5 * v + k] = held ? -1 : 0;
        for (std::size_t i = 1; i < g.size(); ++i) tied_to[g[i]] = g[0];
      }
  }
  for (int v = 0; v < nv; ++v)
    for (int k = 0; k < 5; ++k)
      if (dof_[5 * v + k] == 0 && (k >= 3 || tied_to[v] < 0)) dof_[5 * v + k] = num_free_++;
  for (int v = 0; v < nv; ++v)
    if (tied_to[v] >= 0)
      for (int k = 0; k < 3; ++k) dof_[5 * v + k] = dof_[5 * tied_to[v] + k];

  double load2 = 0.0;
  for (int v = 0; v < nv; ++v) load2 += f_dead_[v].squaredNorm() + moment_[v].squaredNorm();
  load_norm_ = std::sqrt(load2);
  Eigen::AlignedBox3d box;
  for (const auto& x : mesh.vertices) box.extend(x);
  length_scale_ = std::max(box.diagonal().norm(), 1e-12);
  double edges = 0.0;
  for (const auto& q : mesh.quads)
    for (int I = 0; I < 4; ++I)
      edges += (mesh.vertices[q[I]] - mesh.vertices[q[(I + 1) % 4]]).norm();
  mean_edge_ = mesh.quads.empty() ? 1.0 : edges / (4.0 * mesh.numQuads());
  contact_smoothing_ = 1e-4 * mean_edge_;
  anchor_ = nodes_;
  // Edge contact for the solids with edges and rims (tables, pedestals), convex with an exact
  // distance: a smooth surface (plane, sphere, capsule) is met at the nodes as before, and so is a
  // sampled distance field, whose gap is not convex along a line.
  for (const auto& c : problem.colliders)
    edge_surface_.push_back(edge_contact && (dynamic_cast<const BoxSurface*>(c.get()) ||
                                             dynamic_cast<const CylinderSurface*>(c.get())));
  for (int e = 0; e < mesh.numQuads(); ++e)
    for (int I = 0; I < 4; ++I) {
      const int a = mesh.quads[e][I], b = mesh.quads[e][(I + 1) % 4];
      edges_.push_back(
          {std::min(a, b), std::max(a, b), e, a < b ? I : (I + 1) % 4, a < b ? (I + 1) % 4 : I});
    }
  std::sort(edges_.begin(), edges_.end(),
            [](const Edge& x, const Edge& y) { return std::tie(x.a, x.b) < std::tie(y.a, y.b); });
  edges_.erase(std::unique(edges_.begin(), edges_.end(),
                           [](const Edge& x, const Edge& y) { return x.a == y.a && x.b == y.b; }),
               edges_.end());
  buildPattern();
  saved_ = nodes_;
  // Penalty k_c: a hundred times the membrane stiffness E h keeps penetration a fraction of the
  // strains while leaving the tangent well conditioned for the direct solver.
  k_contact_ = contact_stiffness > 0.0
                   ? contact_stiffness
                   : 100.0 * problem.material.young * problem.material.thickness;
}

void ShellModel::setNodes(const std::vector<ShellNode>& nodes) {
  if (nodes.size() != nodes_.size())
    throw InputError("ShellModel::setNodes: " + std::to_string(nodes.size()) + " nodes for " +
                     std::to_string(nodes_.size()) + " vertices");
  nodes_ = nodes;
  saved_ = anchor_ = nodes_;
}

void ShellModel::buildPattern() {
  std::vector<Eigen::Triplet<double>> trip;
  auto free = [&](int v, int k) { return dof_[5 * v + k]; };
  for (const auto& el : elements_)
    for (int a = 0; a < 20; ++a)
      for (int b = 0; b < 20; ++b) {
        const int r = free(el.nodes()[a / 5], a % 5), c = free(el.nodes()[b / 5], b % 5);
        if (r >= 0 && c >= 0) trip.emplace_back(r, c, 0.0);
      }
  const int nv = static_cast<int>(nodes_.size());
  for (int v = 0; v < nv; ++v)
    for (int a = 0; a < 5; ++a)
      for (int b = 0; b < 5; ++b)
        if (free(v, a) >= 0 && free(v, b) >= 0) trip.emplace_back(free(v, a), free(v, b), 0.0);
  pattern_.resize(num_free_, num_free_);
  pattern_.setFromTriplets(trip.begin(), trip.end());
  pattern_.makeCompressed();
  auto slot = [&](int r, int c) { return storageSlot(pattern_, r, c); };
  element_slots_.resize(elements_.size());
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const auto& q = elements_[e].nodes();
    for (int a = 0; a < 20; ++a)
      for (int b = 0; b < 20; ++b)
        element_slots_[e][a * 20 + b] = slot(free(q[a / 5], a % 5), free(q[b / 5], b % 5));
  }
  node_slots_.resize(nv);
  for (int v = 0; v < nv; ++v)
    for (int a = 0; a < 5; ++a)
      for (int b = 0; b < 5; ++b) node_slots_[v][a * 5 + b] = slot(free(v, a), free(v, b));
}

void ShellModel::linearize(double lambda, Eigen::VectorXd& R, Eigen::VectorXd& F0,
                           Eigen::SparseMatrix<double>* K) {
  const int nv = static_cast<int>(nodes_.size());
  R.setZero(num_free_);
  F0.setZero(num_free_);
  auto& fe = element_force_;
  auto& Ke = element_tangent_;
  fe.resize(elements_.size());
  if (K) Ke.resize(elements_.size());
  tbb::parallel_for(std::size_t(0), elements_.size(), [&](std::size_t e) {
    const auto& q = elements_[e].nodes();
    const std::array<const ShellNode*, 4> st = {&nodes_[q[0]], &nodes_[q[1]], &nodes_[q[2]],
                                                &nodes_[q[3]]};
    elements_[e].evaluate(st, fe[e], K ? &Ke[e] : nullptr);
  });

  double* kv = nullptr;
  if (K) {
    if (K->nonZeros() != pattern_.nonZeros() || K->rows() != num_free_) *K = pattern_;
    kv = K->valuePtr();
    std::fill(kv, kv + K->nonZeros(), 0.0);
  }
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const auto& q = elements_[e].nodes();
    for (int a = 0; a < 20; ++a) {
      const int ra = dof_[5 * q[a / 5] + a % 5];
      if (ra >= 0) R[ra] -= fe[e][a];  // -P, eq. (75)
    }
    if (!K) continue;
    const auto& slots = element_slots_[e];
    for (int a = 0; a < 20; ++a)
      for (int b = 0; b < 20; ++b)
        if (slots[a * 20 + b] >= 0) kv[slots[a * 20 + b]] += Ke[e](a, b);
  }

  active_contacts_ = 0;
  // Stabilisation stiffness per unit mass: the weight of a node displaced by one element length.
  const double stab = stabilization_ * problem_.gravity.norm() / mean_edge_;
  for (int v = 0; v < nv; ++v) {
    const ShellNode& node = nodes_[v];
    Eigen::Matrix<double, 5, 1> load;
    Eigen::Matrix<double, 5, 5> Kn = Eigen::Matrix<double, 5, 5>::Zero();
    // Dead forces, and nodal moments doing work on the director rotation omega = t x dt:
    // virtual work (m x t).dt, load stiffness dt.[m]x.Dt (the exponential-map term vanishes as
    // (m x t).t = 0).
    const Eigen::Matrix<double, 3, 2> L = node.frame.basis();
    const Eigen::Vector3d t = node.frame.director();
    load.head<3>() = f_dead_[v];
    load.tail<2>() = L.transpose() * moment_[v].cross(t);
    Kn.bottomRightCorner<2, 2>() = -lambda * L.transpose() * skew(moment_[v]) * L;
    Eigen::Vector3d fc = Eigen::Vector3d::Zero();
    if (stab > 0.0) {  // viscous pseudo-time term, -c m (x - x_n)
      fc -= stab * nodal_mass_[v] * (node.position - anchor_[v].position);
      Kn.topLeftCorner<3, 3>() += stab * nodal_mass_[v] * Eigen::Matrix3d::Identity();
    }
    // Penalty contact, eqs. (33)-(35), active where the node penetrates.
    for (const auto& surface : problem_.colliders) {
      if (edge_surface_[&surface - problem_.colliders.data()]) continue;  // held by the edges
      const SurfaceProjection p = surface->project(node.position);
      const Penalty f = penalty(p.gap);
      if (f.stiffness == 0.0) continue;
      ++active_contacts_;
      fc += f.force * p.normal;
      Kn.topLeftCorner<3, 3>() +=
          f.stiffness * p.normal * p.normal.transpose() - f.force * p.normal_gradient;
    }
    for (int a = 0; a < 5; ++a) {
      const int ra = dof_[5 * v + a];
      if (ra < 0) continue;
      F0[ra] = load[a];
      R[ra] += lambda * load[a] + (a < 3 ? fc[a] : 0.0);
      if (!K) continue;
      for (int b = 0; b < 5; ++b)
        if (node_slots_[v][a * 5 + b] >= 0) kv[node_slots_[v][a * 5 + b]] += Kn(a, b);
    }
  }
  active_contacts_ += edgeContacts(&R, kv, nullptr, nullptr);
}

double ShellModel::energy(double lambda) {
  if (problem_.material.kawabata) return std::numeric_limits<double>::quiet_NaN();
  for (const auto& m : moment_)
    if (m.squaredNorm() > 0.0) return std::numeric_limits<double>::quiet_NaN();
  element_energy_.resize(elements_.size());
  tbb::parallel_for(std::size_t(0), elements_.size(), [&](std::size_t e) {
    const auto& q = elements_[e].nodes();
    element_energy_[e] =
        elements_[e].energy({&nodes_[q[0]], &nodes_[q[1]], &nodes_[q[2]], &nodes_[q[3]]});
  });
  double W = 0.0;
  for (double w : element_energy_) W += w;
  const double stab = stabilization_ * problem_.gravity.norm() / mean_edge_;
  for (std::size_t v = 0; v < nodes_.size(); ++v) {
    const Eigen::Vector3d& x = nodes_[v].position;
    W -= lambda * f_dead_[v].dot(x - problem_.mesh.vertices[v]);
    if (stab > 0.0) W += 0.5 * stab * nodal_mass_[v] * (x - anchor_[v].position).squaredNorm();
    for (std::size_t si = 0; si < problem_.colliders.size(); ++si)
      if (!edge_surface_[si]) W += penaltyEnergy(problem_.colliders[si]->project(x).gap);
  }
  edgeContacts(nullptr, nullptr, &W, nullptr);
  return W;
}

double ShellModel::stepBound(const Eigen::VectorXd& dq) const {
  double move = 0.0, turn = 0.0;
  for (std::size_t v = 0; v < nodes_.size(); ++v) {
    double t2 = 0.0, r2 = 0.0;
    for (int k = 0; k < 5; ++k) {
      const int d = dof_[5 * v + k];
      if (d >= 0) (k < 3 ? t2 : r2) += dq[d] * dq[d];
    }
    move = std::max(move, t2);
    turn = std::max(turn, r2);
  }
  move = std::sqrt(move);
  turn = std::sqrt(turn);
  double f = 1.0;
  if (move > 2.0 * mean_edge_) f = std::min(f, 2.0 * mean_edge_ / move);
  if (turn > 0.5) f = std::min(f, 0.5 / turn);
  return f;
}

namespace {
// 4-point Gauss-Legendre on [0, 1].
constexpr double kGaussPoint[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281,
                                   0.9305681557970263};
constexpr double kGaussWeight[4] = {0.1739274225687269, 0.3260725774312731, 0.3260725774312731,
                                    0.1739274225687269};
}  // namespace

int ShellModel::edgeContacts(Eigen::VectorXd* R, double* kv, double* energy,
                             std::vector<ContactReaction>* reactions) const {
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  int active = 0;
  const double band = 0.5 * contact_smoothing_;
  for (const Edge& ed : edges_) {
    const Eigen::Vector3d xa = nodes_[ed.a].position, xb = nodes_[ed.b].position;
    const Eigen::Vector3d e = xb - xa;
    const double len = e.norm();
    for (std::size_t si = 0; si < problem_.colliders.size(); ++si) {
      if (!edge_surface_[si]) continue;
      const RigidSurface& surface = *problem_.colliders[si];
      const SurfaceProjection pa = surface.project(xa), pb = surface.project(xb);
      // The gap is 1-Lipschitz: nowhere on the edge below (g_a + g_b - |e|) / 2.
      if (0.5 * (pa.gap + pb.gap - len) > band) continue;
      auto gapAt = [&](double s) { return surface.project(xa + s * e); };
      // Least gap along the edge: g(s) is convex for a convex solid; safeguarded Newton on
      // g'(s) = n . e = 0 with g''(s) = e . H e.
      double s_min = 0.0;
      SurfaceProjection p_min = pa;
      if (pb.gap < pa.gap) s_min = 1.0, p_min = pb;
      if (pa.normal.dot(e) < 0.0 && pb.normal.dot(e) > 0.0) {
        double lo = 0.0, hi = 1.0, s = 0.5;
        for (int k = 0; k < 60; ++k) {
          p_min = gapAt(s);
          const double gp = p_min.normal.dot(e), gpp = e.dot(p_min.normal_gradient * e);
          if (std::abs(gp) <= 1e-13 * len || hi - lo < 1e-14) break;
          (gp < 0.0 ? lo : hi) = s;
          const double newton = gpp > 0.0 ? s - gp / gpp : -1.0;
          s = newton > lo && newton < hi ? newton : 0.5 * (lo + hi);
        }
        s_min = s;
      }
      if (p_min.gap >= band) continue;
      // Where the gap rises through the band's edges (-delta/2: the penalty turns from cubic
      // to quadratic; +delta/2: it vanishes) on either side of the least gap, by bisection (g is
      // monotone there). Between these points the integrand is smooth, a cubic or quadratic in
      // g, and Gauss quadrature exact where the gap is linear (a flat top).
      auto crossing = [&](double inside, double outside, double level) {
        for (int k = 0; k < 44; ++k) {
          const double mid = 0.5 * (inside + outside);
          (gapAt(mid).gap < level ? inside : outside) = mid;
        }
        return 0.5 * (inside + outside);
      };
      auto side = [&](double end, double g_end, double* cut) {
        // cut[0]: where the integrand starts (band), cut[1]: where the penalty turns quadratic.
        cut[0] = g_end < band ? end : crossing(s_min, end, band);
        cut[1] = g_end < -band ? end : (p_min.gap < -band ? crossing(s_min, end, -band) : s_min);
        if (g_end >= band && p_min.gap >= -band) cut[1] = s_min;
      };
      double left[2], right[2];
      side(0.0, pa.gap, left);
      side(1.0, pb.gap, right);
      ++active;
      Vec6 force = Vec6::Zero();
      Mat6 Kc = Mat6::Zero();
      // The penalty potential integrated along the edge, int phi(g(x(s))) ds.
      // Where a flat face meets a rounded edge, or an edge a corner, the gap's curvature jumps:
      // split there too (bisection on the regime), so that each piece is smooth.
      std::vector<std::pair<double, double>> pieces;
      for (const auto& [a0, b0] : {std::pair{left[0], left[1]}, std::pair{left[1], s_min},
                                   std::pair{s_min, right[1]}, std::pair{right[1], right[0]}}) {
        if (!(b0 > a0)) continue;
        // The regime: rank k of the curvature projector, H = P_k / distance (0 on a face, 1 on
        // an edge or cylinder, 2 at a corner or sphere), from (trace H / |H|)^2 = k.
        auto flat = [&](double t) {
          const Eigen::Matrix3d H = gapAt(t).normal_gradient;
          const double n = H.norm();
          return n > 0.0 ? std::lround(H.trace() * H.trace() / (n * n)) : 0L;
        };
        const double eps = 1e-9 * (b0 - a0);
        const long fa = flat(a0 + eps), fb = flat(b0 - eps);
        if (fa == fb) {
          pieces.push_back({a0, b0});
          continue;
        }
        double lo = a0, hi = b0;
        for (int k = 0; k < 44; ++k) {
          const double mid = 0.5 * (lo + hi);
          (flat(mid) == fa ? lo : hi) = mid;
        }
        pieces.push_back({a0, 0.5 * (lo + hi)});
        pieces.push_back({0.5 * (lo + hi), b0});
      }
      for (const auto& [from, to] : pieces) {
        if (!(to > from)) continue;
        for (int q = 0; q < 4; ++q) {
          const double s = from + (to - from) * kGaussPoint[q], w = (to - from) * kGaussWeight[q];
          const SurfaceProjection p = gapAt(s);
          const Penalty f = penalty(p.gap);
          if (energy) *energy += w * penaltyEnergy(p.gap);
          if (!R && !kv && !reactions) continue;
          Vec6 grad;
          grad << (1.0 - s) * p.normal, s * p.normal;
          force += w * f.force * grad;
          if (!kv) continue;
          Kc += w * f.stiffness * grad * grad.transpose();
          const double ww[2] = {1.0 - s, s};
          for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j)
              Kc.block<3, 3>(3 * i, 3 * j) -= w * f.force * ww[i] * ww[j] * p.normal_gradient;
        }
      }
      const int v[2] = {ed.a, ed.b};
      if (reactions)
        for (int i = 0; i < 2; ++i)
          reactions->push_back({v[i], static_cast<int>(si), force.segment<3>(3 * i)});
      if (R)
        for (int i = 0; i < 2; ++i)
          for (int k = 0; k < 3; ++k) {
            const int r = dof_[5 * v[i] + k];
            if (r >= 0) (*R)[r] += force[3 * i + k];
          }
      if (!kv) continue;
      const int local[2] = {ed.la, ed.lb};
      const auto& slots = element_slots_[ed.element];
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
              const int slot = slots[(5 * local[i] + a) * 20 + 5 * local[j] + b];
              if (slot >= 0) kv[slot] += Kc(3 * i + a, 3 * j + b);
            }
    }
  }
  return active;
}

ShellModel::Penalty ShellModel::penalty(double gap) const {
  // k_c times the penetration (eq. (35)) with its kink rounded into a parabola over a band of
  // width delta centred on the surface: Newton then converges instead of cycling on nodes that
  // touch and leave, and a cloth laid exactly on a surface is held (stiffness k_c / 2) from the
  // first load step on.
  const double delta = contact_smoothing_, p = 0.5 * delta - gap;
  if (p <= 0.0) return {0.0, 0.0};
  if (p >= delta) return {k_contact_ * (p - 0.5 * delta), k_contact_};
  return {0.5 * k_contact_ * p * p / delta, k_contact_ * p / delta};
}

double ShellModel::penaltyEnergy(double gap) const {
  const double delta = contact_smoothing_, p = 0.5 * delta - gap;
  if (p <= 0.0) return 0.0;
  if (p >= delta)
    return k_contact_ * (delta * delta / 6.0 +
                         0.5 * ((p - 0.5 * delta) * (p - 0.5 * delta) - 0.25 * delta * delta));
  return k_contact_ * p * p * p / (6.0 * delta);
}

void ShellModel::setStabilization(double factor) {
  stabilization_ = factor;
}

void ShellModel::perturbRandom(double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  // One-sided, along +director: a perturbation into a support would start with a penalty force
  // far above the weight.
  std::uniform_real_distribution<double> u(0.0, amplitude);
  for (std::size_t v = 0; v < nodes_.size(); ++v) {
    const double a = u(rng);
    if (dof_[5 * v + 2] >= 0) nodes_[v].position += a * nodes_[v].frame.director();
  }
  saved_ = anchor_ = nodes_;
}

void ShellModel::perturbWaves(double amplitude, int waves) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& x : problem_.mesh.vertices) centre += x;
  centre /= static_cast<double>(nodes_.size());
  double r_max = 0.0;
  for (const auto& x : problem_.mesh.vertices)
    r_max = std::max(r_max, (x - centre).head<2>().norm());
  if (!(r_max > 0.0)) return;
  for (std::size_t v = 0; v < nodes_.size(); ++v) {
    const Eigen::Vector2d d = (problem_.mesh.vertices[v] - centre).head<2>();
    const double r = d.norm() / r_max, theta = std::atan2(d.y(), d.x());
    const double a = amplitude * 0.5 * (1.0 + std::cos(waves * theta)) * r * r;
    if (dof_[5 * v + 2] >= 0) nodes_[v].position += a * nodes_[v].frame.director();
  }
  saved_ = anchor_ = nodes_;
}

void ShellModel::increment(const Eigen::VectorXd& dq) {
  for (std::size_t v = 0; v < nodes_.size(); ++v) {
    double u[5];
    for (int k = 0; k < 5; ++k) {
      const int d = dof_[5 * v + k];
      u[k] = d < 0 ? 0.0 : dq[d];
    }
    nodes_[v].position += Eigen::Vector3d(u[0], u[1], u[2]);
    nodes_[v].frame.rotate(Eigen::Vector2d(u[3], u[4]));
  }
}

std::string ShellModel::unrestrainedRigidModes() const {
  // Each support c contributes the squared components of the six rigid modes (translations, and
  // rotations about the centroid) along its direction; the null space of the 6x6 Gram matrix is
  // what nothing holds. Lengths are scaled by the model size so both kinds weigh alike.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& n : nodes_) centroid += n.position;
  centroid /= static_cast<double>(nodes_.size());
  Eigen::Matrix<double, 6, 6> G = Eigen::Matrix<double, 6, 6>::Zero();
  auto mode = [&](const ShellNode& n, int m) {  // 5 reduced unknowns of rigid mode m at node n
    Eigen::Matrix<double, 5, 1> u = Eigen::Matrix<double, 5, 1>::Zero();
    if (m < 3) {
      u[m] = 1.0;
    } else {
      const Eigen::Vector3d axis = Eigen::Vector3d::Unit(m - 3);
      u.head<3>() = axis.cross(n.position - centroid) / length_scale_;
      u.tail<2>() = n.frame.basis().transpose() * axis.cross(n.frame.director()) / length_scale_;
    }
    return u;
  };
  for (std::size_t v = 0; v < nodes_.size(); ++v) {
    Eigen::Matrix<double, 5, 6> M;
    for (int m = 0; m < 6; ++m) M.col(m) = mode(nodes_[v], m);
    for (int k = 0; k < 5; ++k)
      if (dof_[5 * v + k] < 0) G += M.row(k).transpose() * M.row(k);
    for (const auto& surface : problem_.colliders) {
      const SurfaceProjection p = surface->project(nodes_[v].position);
      if (penalty(p.gap).stiffness == 0.0) continue;
      const Eigen::Matrix<double, 1, 6> c = p.normal.transpose() * M.topRows<3>();
      G += c.transpose() * c;
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(G);
  const double top = std::max(eig.eigenvalues().maxCoeff(), 1e-300);
  const char* names[6] = {"sliding along x", "sliding along y", "moving along z",
                          "turning about x", "turning about y", "turning about z"};
  std::string out;
  for (int i = 0; i < 6; ++i) {
    if (eig.eigenvalues()[i] > 1e-10 * top) continue;
    int dominant;
    eig.eigenvectors().col(i).cwiseAbs().maxCoeff(&dominant);
    out += (out.empty() ? "" : ", ") + std::string(names[dominant]);
  }
  return out;
}

std::vector<ContactReaction> ShellModel::reactions() const {
  std::vector<ContactReaction> out;
  for (std::size_t v = 0; v < nodes_.size(); ++v)
    for (std::size_t s = 0; s < problem_.colliders.size(); ++s) {
      if (edge_surface_[s]) continue;
      const SurfaceProjection p = problem_.colliders[s]->project(nodes_[v].position);
      const Penalty f = penalty(p.gap);
      if (f.force > 0.0)
        out.push_back({static_cast<int>(v), static_cast<int>(s), f.force * p.normal});
    }
  edgeContacts(nullptr, nullptr, nullptr, &out);
  return out;
}

}  // namespace chs
