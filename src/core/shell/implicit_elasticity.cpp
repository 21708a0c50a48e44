#include "cloth_hair_sim/core/shell/implicit_elasticity.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_quadrature.h"
#include "cloth_hair_sim/core/shell/stencil_hessian.h"
#include "cloth_hair_sim/core/solver/permuted_cholesky.h"

namespace chs {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// Each thread's sums of the face blocks (9 per block of the pattern), zero between assemblies.
struct ImplicitElasticity::Workspace {
  tbb::enumerable_thread_specific<std::vector<double>> blocks;
  explicit Workspace(std::size_t values) : blocks(std::vector<double>(values, 0.0)) {}
};

ImplicitElasticity::ImplicitElasticity(const std::vector<KirchhoffLovePoint>& points,
                                       int num_points, ControlPointLinks links)
    : points_(points),
      n_(num_points),
      links_(std::move(links)),
      fibres_(fibreRanges(points)),
      factor_(std::make_unique<PermutedCholesky>()) {
  if (static_cast<int>(links_.owner.size()) != n_ || static_cast<int>(links_.map.size()) != n_)
    throw InputError("implicit elasticity: links for " + std::to_string(links_.owner.size()) +
                     " points, the shell has " + std::to_string(n_));
  for (int p = 0; p < n_; ++p) {
    const int o = links_.owner[p];
    if (o < 0 || o >= n_ || links_.owner[o] != o)
      throw InputError("implicit elasticity: point " + std::to_string(p) + " has owner " +
                       std::to_string(o) + ", which is not its own owner");
  }
  const std::vector<int>& owner = links_.owner;
  std::vector<std::vector<int>> cols(n_);
  for (int p = 0; p < n_; ++p) {
    cols[p].push_back(p);  // every point: slaved ones get an identity row
    cols[owner[p]].push_back(owner[p]);
  }
  for (const FibreRange& f : fibres_) {
    const std::vector<int>& st = points_[f.first].stencil().points;
    for (int k : st)
      for (int l : st) cols[owner[k]].push_back(owner[l]);
  }
  block_start_.assign(n_ + 1, 0);
  for (int r = 0; r < n_; ++r) {
    std::sort(cols[r].begin(), cols[r].end());
    cols[r].erase(std::unique(cols[r].begin(), cols[r].end()), cols[r].end());
    block_start_[r + 1] = block_start_[r] + static_cast<int>(cols[r].size());
    block_col_.insert(block_col_.end(), cols[r].begin(), cols[r].end());
  }
  auto block = [&](int r, int c) {
    const auto first = block_col_.begin() + block_start_[r];
    const auto last = block_col_.begin() + block_start_[r + 1];
    return static_cast<int>(std::lower_bound(first, last, c) - block_col_.begin());
  };
  for (const FibreRange& f : fibres_) {
    slot_start_.push_back(static_cast<int>(slot_.size()));
    const std::vector<int>& st = points_[f.first].stencil().points;
    for (int k : st)
      for (int l : st) slot_.push_back(block(owner[k], owner[l]));
  }
  for (int f = 0; f < static_cast<int>(fibres_.size()); ++f)
    if (f == 0 || points_[fibres_[f].first].stencil().points !=
                      points_[fibres_[f - 1].first].stencil().points)
      groups_.push_back(f);
  groups_.push_back(static_cast<int>(fibres_.size()));

  double volume = 0.0;
  fibre_share_.assign(fibres_.size(), 0.0);
  for (std::size_t f = 0; f < fibres_.size(); ++f) {
    for (int q = fibres_[f].first; q < fibres_[f].last; ++q)
      fibre_share_[f] += points_[q].referenceVolume();
    volume += fibre_share_[f];
  }
  for (double& share : fibre_share_) share /= volume > 0.0 ? volume : 1.0;
  obstacle_gradient_.assign(n_, Vec3::Zero());

  const int nb = static_cast<int>(block_col_.size());
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(9 * static_cast<std::size_t>(nb));
  for (int r = 0; r < n_; ++r)
    for (int b = block_start_[r]; b < block_start_[r + 1]; ++b)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) triplets.emplace_back(3 * r + i, 3 * block_col_[b] + j, 0.0);
  workspace_ = std::make_unique<Workspace>(9 * static_cast<std::size_t>(nb));
  matrix_.resize(3 * n_, 3 * n_);
  matrix_.setFromTriplets(triplets.begin(), triplets.end());
  // The Newton matrix is assembled in its fill-reducing order (solver/permuted_cholesky.h).
  factor_ = std::make_unique<PermutedCholesky>(fewestFlopsOrder(matrix_));
  const std::vector<int>& perm = factor_->order();
  std::vector<int> position(3 * n_);  // of each unknown in the factorised order
  for (int k = 0; k < 3 * n_; ++k) position[perm[k]] = k;
  // The lower triangle in that order alone, from the blocks (r, c <= r): entry (i, j) of block
  // (r, c) lands where its row comes after its column, else on its mirror (the same value); a
  // diagonal block's entry above the diagonal is left to its mirror in the block (index -1).
  value_index_.assign(9 * static_cast<std::size_t>(nb), -1);
  triplets.clear();
  std::vector<int> entry;  // the value slot 9 b + 3 i + j of each triplet
  for (int r = 0; r < n_; ++r)
    for (int b = block_start_[r]; b < block_start_[r + 1] && block_col_[b] <= r; ++b)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const int row = position[3 * r + i], col = position[3 * block_col_[b] + j];
          if (block_col_[b] == r && row < col) continue;
          triplets.emplace_back(std::max(row, col), std::min(row, col), 0.0);
          entry.push_back(9 * b + 3 * i + j);
        }
  matrix_.setFromTriplets(triplets.begin(), triplets.end());
  for (std::size_t t = 0; t < triplets.size(); ++t)
    value_index_[entry[t]] = static_cast<int>(
        &matrix_.coeffRef(triplets[t].row(), triplets[t].col()) - matrix_.valuePtr());
}

ImplicitElasticity::~ImplicitElasticity() = default;

namespace {

// IPC's smoothed Coulomb magnitude (Li et al. 2020, (14)-(15)): f1(y) = 2 y / eps - y^2 / eps^2
// below eps, 1 above, and f0 with f0' = f1, f0(eps) = eps.
double frictionF0(double y, double eps) {
  return y < eps ? y * y / eps - y * y * y / (3.0 * eps * eps) + eps / 3.0 : y;
}
double frictionF1(double y, double eps) {
  return y < eps ? 2.0 * y / eps - y * y / (eps * eps) : 1.0;
}

}  // namespace

Vec3 ImplicitElasticity::samplePoint(int i, const std::vector<Vec3>& x) const {
  const int nf = static_cast<int>(fibres_.size());
  return i < nf ? points_[fibres_[i].first].stencil().position(x) : x[i - nf];
}

double ImplicitElasticity::sampleStiffness(int i, const std::vector<double>& mass,
                                           double total_mass, double dt) const {
  const int nf = static_cast<int>(fibres_.size());
  const ObstaclePenalty& o = *obstacles_;
  return i < nf ? o.stiffness * fibre_share_[i] * total_mass / (dt * dt)
                : o.point_stiffness * mass[i - nf] / (dt * dt);
}

void ImplicitElasticity::lagContacts(const std::vector<double>& mass, double dt) {
  const int ns = static_cast<int>(fibres_.size()) + n_;
  lagged_.assign(ns, LaggedContact());
  if (!obstacles_ || !obstacles_->active()) return;
  const ObstaclePenalty& o = *obstacles_;
  for (LaggedContact& c : lagged_) c.offset = o.offset;
  if (!o.start) return;
  if (static_cast<int>(normal_force_.size()) != ns) normal_force_.assign(ns, 0.0);
  double total_mass = 0.0;
  for (double m : mass) total_mass += m;
  tbb::parallel_for(0, ns, [&](int i) {
    const double kappa = sampleStiffness(i, mass, total_mass, dt);
    if (!(kappa > 0.0)) return;
    const Vec3 start = samplePoint(i, *o.start);
    const ObstacleQuery q = o.nearest(start);
    if (q.obstacle < 0 || !(q.distance < o.offset)) return;
    LaggedContact& c = lagged_[i];
    // A sample that carried a load at the last solve's end sat its sag lambda / kappa below its
    // target: the rise is counted from there, so that a sample carrying more than its own weight
    // (under a fold, over the sphere's rim) still rises into the band instead of sinking a little
    // deeper each step for the grid's stages to push back out (docs/BENCHMARKS.md, 2026-12-07).
    const double sag = normal_force_[i] > 0.0 ? normal_force_[i] / kappa : 0.0;
    c.offset = std::min(o.offset, q.distance + o.rise + sag);
    // The normal force: the last solve's, or (a sample that was not pressed then) the penalty's
    // at the start, so that a cloth laid on a slope holds from its first step.
    const double normal = normal_force_[i] > 0.0
                              ? normal_force_[i]
                              : kappa * std::clamp(c.offset - q.distance, 0.0, o.offset);
    if (!(q.friction > 0.0) || !(normal > 0.0)) return;
    c.obstacle = q.obstacle;
    c.mu_lambda = q.friction * normal;
    c.normal = q.normal;
    c.start = start;
    c.slide = dt * q.velocity;
  });
}

double ImplicitElasticity::obstaclePenalty(const std::vector<Vec3>& x,
                                           const std::vector<double>& mass, double dt) {
  obstacle_gradient_.assign(n_, Vec3::Zero());
  pushes_.clear();
  normal_.clear();
  if (!obstacles_ || !obstacles_->active()) return 0.0;
  double total_mass = 0.0;
  for (double m : mass) total_mass += m;
  const int nf = static_cast<int>(fibres_.size()), ns = nf + n_;
  contacts_.resize(ns);
  contact_hessian_.resize(ns);
  std::vector<double> energy(ns, 0.0);
  normal_.assign(ns, 0.0);
  const ObstaclePenalty& o = *obstacles_;
  const double eps = o.friction_velocity * dt;
  tbb::parallel_for(0, ns, [&](int i) {
    ObstaclePush& c = contacts_[i];
    Mat3& H = contact_hessian_[i];
    c.obstacle = -1;
    const double kappa = sampleStiffness(i, mass, total_mass, dt);
    if (!(kappa > 0.0)) return;
    c.point = samplePoint(i, x);
    c.force.setZero();
    H.setZero();
    const LaggedContact& f = lagged_[i];
    const ObstacleQuery q = o.nearest(c.point);
    if (q.obstacle >= 0 && q.distance < f.offset) {
      // Quadratic over a band of the offset's width, linear beyond (a depth left by the grid
      // then costs a bounded push, not a kick that grows with its square).
      const double depth = f.offset - q.distance;
      c.obstacle = q.obstacle;
      normal_[i] = kappa * std::min(depth, o.offset);
      c.force = normal_[i] * q.normal;
      if (depth <= o.offset) {
        H = kappa * q.normal * q.normal.transpose();
        energy[i] = 0.5 * kappa * depth * depth;
      } else {
        energy[i] = kappa * o.offset * (depth - 0.5 * o.offset);
      }
    }
    if (f.mu_lambda > 0.0) {
      const Mat3 T = Mat3::Identity() - f.normal * f.normal.transpose();
      const Vec3 u = T * (c.point - f.start - f.slide);
      const double y = u.norm();
      energy[i] += f.mu_lambda * frictionF0(y, eps);
      const double f1_over_y = y > 0.0 ? frictionF1(y, eps) / y : 2.0 / eps;
      c.force -= f.mu_lambda * f1_over_y * u;
      // IPC's matrix: f1' along the slip (zero when sliding), f1 / y across it; both >= 0.
      const Vec3 along = y > 0.0 ? Vec3(u / y) : Vec3::Zero();
      const double f1_prime = y < eps ? 2.0 / eps - 2.0 * y / (eps * eps) : 0.0;
      H += f.mu_lambda *
           (f1_prime * along * along.transpose() + f1_over_y * (T - along * along.transpose()));
      if (c.obstacle < 0) c.obstacle = f.obstacle;
    }
  });
  double total = 0.0;
  for (int i = 0; i < ns; ++i) {
    const ObstaclePush& c = contacts_[i];
    if (c.obstacle < 0) continue;
    total += energy[i];
    if (i < nf) {
      const SurfaceStencil& st = points_[fibres_[i].first].stencil();
      for (int k = 0; k < st.size(); ++k) obstacle_gradient_[st.points[k]] -= st.w[k] * c.force;
    } else {
      obstacle_gradient_[i - nf] -= c.force;
    }
    pushes_.push_back(c);
  }
  return total;
}

double ImplicitElasticity::incrementalPotential(const std::vector<Vec3>& x,
                                                const std::vector<Vec3>& x_hat,
                                                const std::vector<double>& mass, double dt,
                                                const HenckyLamina& material, bool with_gradient) {
  double phi = kirchhoffLoveEnergy(points_, material, x, with_gradient ? &gradient_ : nullptr);
  phi += obstaclePenalty(x, mass, dt);
  for (int p = 0; p < n_; ++p) phi += 0.5 * mass[p] * (x[p] - x_hat[p]).squaredNorm() / (dt * dt);
  return phi;
}

void ImplicitElasticity::assemble(const std::vector<Vec3>& x, const std::vector<double>& mass,
                                  double dt, const std::vector<Vec3>& free,
                                  const HenckyLamina& material, bool projected,
                                  ImplicitElasticityResult& result) {
  const auto start = std::chrono::steady_clock::now();
  obstaclePenalty(x, mass, dt);  // the contacts at x (the last potential may be a rejected trial)
  const bool contact = obstacles_ && obstacles_->active();
  tbb::enumerable_thread_specific<std::vector<double>>& local = workspace_->blocks;
  const std::vector<int>& owner = links_.owner;
  tbb::parallel_for(0, static_cast<int>(groups_.size()) - 1, [&](int group) {
    // The fibres of one face share its stencil points: their blocks are summed per face
    // (shell/stencil_hessian.h) and scattered once per face, not once per fibre.
    const int first = groups_[group], last = groups_[group + 1];
    const std::vector<int>& points = points_[fibres_[first].first].stencil().points;
    const int S = static_cast<int>(points.size());
    thread_local StencilHessian K;
    K.reset(S);
    for (int f = first; f < last; ++f) {
      const SurfaceStencil& st = points_[fibres_[f].first].stencil();
      const StencilSums sums = MidSurfaceFrame::sums(st, x);
      K.add(st, projected ? projectedFibreHessian(points_, fibres_[f], material, sums)
                          : fibreHessian(points_, fibres_[f], material, sums));
      if (contact && contacts_[f].obstacle >= 0) K.addAtPosition(st, contact_hessian_[f]);
    }
    K.finish();
    std::vector<double>& v = local.local();
    const int* slot = &slot_[slot_start_[first]];
    for (int k = 0; k < S; ++k) {
      const int pk = points[k];
      // Block (l, k) is block (k, l) transposed: half the pairs suffice, each summed into the
      // block of the lower block triangle, (owner[pk], owner[pl]) or its transpose.
      for (int l = 0; l <= k; ++l) {
        Mat3 B = K.block(k, l);
        const int pl = points[l];
        if (owner[pk] != pk) B = links_.map[pk].transpose() * B;
        if (owner[pl] != pl) B = B * links_.map[pl];
        if (owner[pk] >= owner[pl]) {
          double* dst = &v[9 * static_cast<std::size_t>(slot[k * S + l])];
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) dst[3 * i + j] += B(i, j);
        }
        if (owner[pk] > owner[pl] || l == k) continue;
        double* dst = &v[9 * static_cast<std::size_t>(slot[l * S + k])];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) dst[3 * i + j] += B(j, i);
      }
    }
  });
  // Per owner: the mass term and the control points' obstacle Hessians, folded (J^T M J).
  std::vector<Mat3> diagonal(n_, Mat3::Zero());
  for (int p = 0; p < n_; ++p) {
    Mat3 M = mass[p] / (dt * dt) * Mat3::Identity();
    if (contact && contacts_[fibres_.size() + p].obstacle >= 0)
      M += contact_hessian_[fibres_.size() + p];
    diagonal[owner[p]] += links_.map[p].transpose() * M * links_.map[p];
  }
  std::vector<double*> parts;
  for (std::vector<double>& v : local) parts.push_back(v.data());
  // Held unknowns (slaved points, pins, fixed components) as identity rows and columns: their
  // increments solve to zero. The threads' sums are cleared as they are read, for the next call.
  std::vector<char> held(3 * n_);
  for (int p = 0; p < n_; ++p)
    for (int i = 0; i < 3; ++i) held[3 * p + i] = owner[p] != p || free[p][i] == 0.0;
  double* a = matrix_.valuePtr();
  tbb::parallel_for(tbb::blocked_range<int>(0, n_), [&](const tbb::blocked_range<int>& rows) {
    for (int r = rows.begin(); r < rows.end(); ++r)
      for (int b = block_start_[r]; b < block_start_[r + 1] && block_col_[b] <= r; ++b) {
        const int c = block_col_[b];
        double B[9] = {};
        if (r == c)
          for (int e = 0; e < 9; ++e) B[e] = diagonal[r](e / 3, e % 3);
        for (double* part : parts)
          for (int e = 0; e < 9; ++e) {
            B[e] += part[9 * b + e];
            part[9 * b + e] = 0.0;
          }
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            if (const int e = value_index_[9 * b + 3 * i + j]; e >= 0)
              a[e] = held[3 * r + i] || held[3 * c + j] ? (r == c && i == j ? 1.0 : 0.0)
                                                        : B[3 * i + j];
      }
  });
  const auto assembled = std::chrono::steady_clock::now();
  result.assembly_seconds += std::chrono::duration<double>(assembled - start).count();
  // On one BLAS thread (common/blas_threads.h): lent a second one, the towel's 2028 unknowns
  // factorised in 15 ms instead of 22-26, but its worker then spun in sched_yield through the
  // TBB stages that followed, a third of a core in the node's demo (perf), and whole runs were
  // slower (docs/BENCHMARKS.md, 2026-12-06).
  factored_ = factor_->factorize(matrix_);
  result.factorization_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - assembled).count();
  factored_dt_ = dt;
  factored_free_ = free;
}

void ImplicitElasticity::refresh(const std::vector<Vec3>& x, const std::vector<double>& mass,
                                 double dt, const std::vector<Vec3>& free,
                                 const HenckyLamina& material, ImplicitElasticityResult& result) {
  if (!exact_refused_) {
    assemble(x, mass, dt, free, material, false, result);
    if (factored_) return;
    exact_refused_ = true;  // for the rest of this solve: a refusal costs a factorisation
    ++result.exact_refusals;
  }
  assemble(x, mass, dt, free, material, true, result);
}

ImplicitElasticityResult ImplicitElasticity::solve(
    std::vector<Vec3>& x, const std::vector<Vec3>& x_hat, const std::vector<double>& mass,
    double dt, const std::vector<Vec3>& free, const HenckyLamina& material,
    const std::function<void(std::vector<Vec3>&)>& place, const ImplicitElasticitySettings& s) {
  const std::size_t n = static_cast<std::size_t>(n_);
  if (x.size() != n || x_hat.size() != n || mass.size() != n || free.size() != n)
    throw InputError("implicit elasticity: arrays of " + std::to_string(x.size()) + ", " +
                     std::to_string(x_hat.size()) + ", " + std::to_string(mass.size()) + ", " +
                     std::to_string(free.size()) + " entries for " + std::to_string(n_) +
                     " points");
  const std::vector<int>& owner = links_.owner;
  // Folded mass of each owner (the diagonal of J^T M J), for the residual's weights.
  std::vector<double> folded_mass(n, 0.0);
  double total_mass = 0.0;
  for (int p = 0; p < n_; ++p) {
    folded_mass[owner[p]] += mass[p] * links_.map[p].squaredNorm() / 3.0;
    total_mass += mass[p];
  }
  Eigen::VectorXd g(3 * n_), g_elastic(3 * n_);
  auto held = [&](int p, int a) { return owner[p] != p || free[p][a] == 0.0; };
  // dPhi/dy of the unknowns y (owners' free axes) and its elastic part dPsi/dy, and the residual
  // norm dt |g| weighted by mass.
  auto foldGradient = [&]() {
    g.setZero();
    g_elastic.setZero();
    for (int p = 0; p < n_; ++p) {
      g_elastic.segment<3>(3 * owner[p]) +=
          links_.map[p].transpose() * (gradient_[p] + obstacle_gradient_[p]);
      g.segment<3>(3 * owner[p]) +=
          links_.map[p].transpose() * (mass[p] * (x[p] - x_hat[p]) / (dt * dt));
    }
    g += g_elastic;
    double r2 = 0.0;
    for (int p = 0; p < n_; ++p) {
      for (int a = 0; a < 3; ++a)
        if (held(p, a)) g(3 * p + a) = g_elastic(3 * p + a) = 0.0;
      if (owner[p] == p && folded_mass[p] > 0.0)
        r2 += dt * dt * g.segment<3>(3 * p).squaredNorm() / folded_mass[p];
    }
    return std::sqrt(r2 / total_mass);
  };
  // The mass term's Hessian J^T M J / dt^2 applied to an increment of the unknowns.
  std::vector<Mat3> folded_mass_block(n, Mat3::Zero());
  for (int p = 0; p < n_; ++p)
    folded_mass_block[owner[p]] += mass[p] * links_.map[p].transpose() * links_.map[p];
  auto massTimes = [&](const Eigen::VectorXd& v) {
    Eigen::VectorXd mv(3 * n_);
    for (int p = 0; p < n_; ++p) mv.segment<3>(3 * p) = folded_mass_block[p] * v.segment<3>(3 * p);
    for (int p = 0; p < n_; ++p)
      for (int a = 0; a < 3; ++a)
        if (held(p, a)) mv(3 * p + a) = 0.0;
    return Eigen::VectorXd(mv / (dt * dt));
  };
  // L-BFGS on the kept factor (Liu, Bouaziz and Kavan 2017 precondition it with a constant
  // matrix; here it is the last factorised Hessian): the direction -H g from the two-loop
  // recursion over the kept pairs, the elastic curvature pairs (s, y_Psi) completed by this step's
  // exact mass term, y = y_Psi + M s / dt^2, so pairs of earlier steps (another dt) stay valid.
  auto direction = [&]() {
    Eigen::VectorXd q = g;
    const int m = static_cast<int>(pair_s_.size());
    std::vector<double> alpha(m), rho(m);
    std::vector<Eigen::VectorXd> y(m);
    for (int i = m - 1; i >= 0; --i) {
      y[i] = pair_y_[i] + massTimes(pair_s_[i]);
      rho[i] = 1.0 / y[i].dot(pair_s_[i]);
      alpha[i] = rho[i] * pair_s_[i].dot(q);
      q -= alpha[i] * y[i];
    }
    Eigen::VectorXd r = factor_->solve(q);
    for (int i = 0; i < m; ++i) r += pair_s_[i] * (alpha[i] - rho[i] * y[i].dot(r));
    return Eigen::VectorXd(-r);
  };
  ImplicitElasticityResult result;
  exact_refused_ = false;
  obstacles_ = &s.obstacles;
  lagContacts(mass, dt);
  double phi = incrementalPotential(x, x_hat, mass, dt, material, true);
  result.initial_residual = result.residual = foldGradient();
  // Residual reduction of the last iteration, and whether that iteration ran on a factor of an
  // earlier iterate (a fresh factor that converges slowly is not refreshed again at once: the
  // Hessian's projection or the contacts' kinks, not its age, are what slow it).
  double ratio = 0.0;
  bool stale = true;
  std::vector<Vec3> trial(n);
  while (result.residual >= s.tolerance && result.iterations < s.max_iterations) {
    // The CFL step varies a little from step to step: a factor of a step within 25 % still
    // serves (its mass term is off by less than the stiffness it lags by). In Newton mode the
    // second iteration runs on the first one's factor with its secant pair: on the swinging
    // towel the second iteration's exact step left the residual where it was or raised it in 8
    // of 9 traced solves (3.6e-3 -> 3.7e-3, 1.3e-2 -> 6.9e-2 m/s: the soft modes' correction;
    // one fell 5 times), and the third converged quadratically from there (docs/BENCHMARKS.md).
    const bool newton_refresh = newton_ && result.iterations != 1;
    const double refresh_ratio = pushes_.empty() ? s.refresh_ratio : s.contact_refresh_ratio;
    bool fresh = !factored_ || !s.reuse_factorization || std::abs(dt / factored_dt_ - 1.0) > 0.25 ||
                 free != factored_free_ || (stale && ratio > refresh_ratio) || newton_refresh;
    bool accepted = false, fresh_used = false;
    for (int attempt = 0; attempt < 2 && !accepted; ++attempt) {
      if (fresh || !factored_) {
        refresh(x, mass, dt, free, material, result);
        pair_s_.clear();  // the new factor holds what they approximated
        pair_y_.clear();
        ++result.factorizations;
        fresh_used = true;
        if (!factored_) break;  // not positive definite: cannot happen with the projection
      }
      const Eigen::VectorXd d = direction();
      const double slope = g.dot(d);
      double alpha = 1.0;
      for (int cut = 0; cut <= 12; ++cut, alpha *= 0.5) {
        trial = x;
        for (int p = 0; p < n_; ++p)
          if (owner[p] == p) trial[p] += alpha * d.segment<3>(3 * p);
        place(trial);
        std::swap(trial, x);
        const double phi_trial = incrementalPotential(x, x_hat, mass, dt, material, true);
        ++result.potential_evaluations;
        // Armijo, with room for round-off once Phi has nearly stopped changing.
        if (std::isfinite(phi_trial) &&
            phi_trial <= phi + 1e-4 * alpha * slope + 1e-13 * std::abs(phi)) {
          phi = phi_trial;
          accepted = true;
          break;
        }
        std::swap(trial, x);
        ++result.line_search_cuts;
      }
      // A lagged factorisation whose direction the line search cannot use: refresh once.
      if (fresh_used) break;
      fresh = true;
    }
    stale = !fresh_used;
    if (!accepted) {
      incrementalPotential(x, x_hat, mass, dt, material, true);  // gradient_ of x again
      break;
    }
    ++result.iterations;
    const Eigen::VectorXd g_elastic_before = g_elastic;
    Eigen::VectorXd step(3 * n_);
    for (int p = 0; p < n_; ++p) step.segment<3>(3 * p) = x[p] - trial[p];
    for (int p = 0; p < n_; ++p)
      for (int a = 0; a < 3; ++a)
        if (held(p, a)) step(3 * p + a) = 0.0;
    const double residual = foldGradient();
    // A pair enters if its curvature is positive (then every H of the recursion stays SPD).
    const Eigen::VectorXd y_elastic = g_elastic - g_elastic_before;
    if (s.history > 0 && (y_elastic + massTimes(step)).dot(step) > 1e-12 * step.squaredNorm()) {
      if (static_cast<int>(pair_s_.size()) == s.history) {
        pair_s_.erase(pair_s_.begin());
        pair_y_.erase(pair_y_.begin());
      }
      pair_s_.push_back(step);
      pair_y_.push_back(y_elastic);
    }
    ratio = residual / std::max(result.residual, std::numeric_limits<double>::min());
    result.residual = residual;
    // A kept factor could not lower the residual at all: the cloth has turned or deformed beyond
    // what it describes (the towel at 1/60 s, each step turning it 0.1 rad). Newton then pays
    // for a factorisation per iteration, quadratic on the exact Hessian, unless a sample touches
    // an obstacle: the penalty's and friction's kinks slow Newton to the chord's rate. It stays
    // on into the next solves: a first iteration on the last step's factor, and chord iterations
    // between fresh ones, led the Newton iterations astray (0.36 -> 1.5 m/s).
    if (stale && ratio >= 1.0 && pushes_.empty()) newton_ = true;
  }
  result.converged = result.residual < s.tolerance;
  // Back to the kept factor once Newton converges at once (the motion has calmed) or not at all.
  if (newton_ && (result.iterations <= 2 || !result.converged)) newton_ = false;
  obstaclePenalty(x, mass, dt);  // pushes_ at the returned iterate
  normal_force_ = normal_;       // the next step's friction bound
  obstacles_ = nullptr;
  return result;
}

}  // namespace chs
