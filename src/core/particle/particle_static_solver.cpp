#include "cloth_hair_sim/core/particle/particle_static_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/particle/particle_contact.h"
#include "cloth_hair_sim/core/particle/particle_loads.h"

namespace chs {

namespace {
using Vec3 = Eigen::Vector3d;

void requirePositive(double value, const char* name, bool zero_ok) {
  if (!std::isfinite(value) || value < 0.0 || (!zero_ok && value == 0.0)) {
    std::ostringstream s;
    s << "particle settings: " << name << " = " << value << " must be "
      << (zero_ok ? "positive (or 0 for automatic)" : "positive");
    throw InputError(s.str());
  }
}

void validateSettings(const ParticleSettings& s, int num_vertices) {
  requirePositive(s.c_disp, "C_disp", true);
  requirePositive(s.c_acc, "C_acc", true);
  if (!(s.momentum >= 0.0 && s.momentum < 1.0))
    throw InputError("particle settings: momentum must lie in [0, 1)");
  requirePositive(s.displacement_tolerance, "displacement tolerance", false);
  requirePositive(s.force_tolerance, "force tolerance", false);
  requirePositive(s.contact_tolerance, "contact tolerance", true);
  requirePositive(s.sewing_stiffness, "sewing stiffness", true);
  requirePositive(s.seam_join_distance, "seam join distance", true);
  for (double f : {s.network.stretch_compression, s.network.shear_compression})
    if (!(f > 0.0 && f <= 1.0))
      throw InputError("particle settings: D' and B' in compression must lie in (0, 1]");
  if (s.max_iterations < 1) throw InputError("particle settings: max_iterations must be >= 1");
  if (s.max_sewing_iterations < 1)
    throw InputError("particle settings: max_sewing_iterations must be >= 1");
  if (s.progress_interval < 1)
    throw InputError("particle settings: progress_interval must be >= 1");
  if (!s.initial_positions.empty()) {
    if (static_cast<int>(s.initial_positions.size()) != num_vertices)
      throw InputError("particle settings: initial_positions has " +
                       std::to_string(s.initial_positions.size()) + " entries for " +
                       std::to_string(num_vertices) + " vertices");
    for (std::size_t i = 0; i < s.initial_positions.size(); ++i)
      if (!s.initial_positions[i].allFinite())
        throw InputError("particle settings: initial position of vertex " + std::to_string(i) +
                         " is not finite");
  }
}

// 1 where a vertex may move along an axis, 0 where a boundary condition holds it.
std::vector<Vec3> freeAxes(const BoundaryConditions& bc, int n) {
  std::vector<Vec3> mask(n, Vec3::Ones());
  for (int v : bc.clamped) mask[v].setZero();
  for (int v : bc.pinned) mask[v].setZero();
  for (const auto& f : bc.fixed_components) mask[f.vertex][f.axis] = 0.0;
  return mask;
}

// The relaxation loop shared by the sewing and the drape phases.
struct Relaxation {
  Relaxation(const ParticleNetwork& network, const ParticleLoads& loads, const SeamGroups& seams,
             const RigidSurfaces& surfaces, const ParticleSettings& settings,
             const ProgressCallback& progress, std::vector<Vec3> mask, double b)
      : network(network),
        loads(loads),
        seams(seams),
        surfaces(surfaces),
        settings(settings),
        progress(progress),
        mask(std::move(mask)),
        b(b) {}

  const ParticleNetwork& network;
  const ParticleLoads& loads;
  const SeamGroups& seams;
  const RigidSurfaces& surfaces;
  const ParticleSettings& settings;
  const ProgressCallback& progress;
  std::vector<Vec3> mask;
  double b = 1.0;

  std::vector<Vec3> x, disp, force, reaction;
  std::vector<int> contact_surface;
  int iterations = 0;
  double max_disp = 0.0, max_force = 0.0;
  int active_contacts = 0;
  std::vector<ProgressEvent> history;

  enum class Outcome { kConverged, kStopped, kLimit, kNonFinite, kCancelled };

  // One phase. sewing: sewing springs, no loads/obstacles; else: loads, obstacles, joined seams.
  // stop(): extra exit test (seams met). Returns how the phase ended.
  template <typename Stop>
  Outcome run(bool sewing, double c_disp, double beta, double sewing_k, double force_ref,
              int max_iterations, int load_step, Stop stop) {
    const int n = static_cast<int>(x.size());
    const double contact_tol =
        settings.contact_tolerance > 0.0 ? settings.contact_tolerance : 1e-6 * b;
    const bool joined = !sewing && !seams.empty();
    force.assign(n, Vec3::Zero());
    reaction.assign(n, Vec3::Zero());
    contact_surface.assign(n, -1);
    std::vector<Vec3> step(n), normal(n);
    for (int it = 1; it <= max_iterations; ++it) {
      if (cancelRequested(settings.cancel)) return Outcome::kCancelled;
      // Steps 2-4: weight and loads, internal reactions, sewing.
      std::fill(force.begin(), force.end(), Vec3::Zero());
      network.addForces(x, force);
      if (sewing)
        seams.addSewingForces(x, sewing_k, force);
      else
        loads.addForces(x, 1.0, 1.0, force);
      if (joined) seams.average(force);
      // Step 5: collisions cancel the inward normal component (seed 000 section 3.2.2).
      active_contacts = 0;
      double power = 0.0;
      max_force = 0.0;
      for (int i = 0; i < n; ++i) {
        reaction[i].setZero();
        contact_surface[i] = sewing ? -1 : touchingSurface(surfaces, x[i], contact_tol, &normal[i]);
        if (contact_surface[i] >= 0) {
          reaction[i] = cancelInwardComponent(normal[i], force[i]);
          if (reaction[i].squaredNorm() > 0.0) ++active_contacts;
        }
        force[i] = force[i].cwiseProduct(mask[i]);
        power += force[i].dot(disp[i]);
        max_force = std::max(max_force, force[i].norm());
      }
      // The pseudo-load C_acc Disp^(k-1) (eq. 49) helps only while it points downhill.
      const double momentum = settings.restart && power < 0.0 ? 0.0 : beta;
      // Step 6: Disp = C_disp (F + C_acc Disp^(k-1)); the pseudo-load is part of the resultant
      // the collision algorithm sees, so it cannot push a node into an obstacle either.
      max_disp = 0.0;
      bool finite = true;
      for (int i = 0; i < n; ++i) {
        step[i] = c_disp * force[i] + momentum * disp[i];
        if (contact_surface[i] >= 0) cancelInwardComponent(normal[i], step[i]);
        step[i] = step[i].cwiseProduct(mask[i]);
        max_disp = std::max(max_disp, step[i].norm());
        finite = finite && step[i].allFinite();
      }
      if (!finite) return Outcome::kNonFinite;
      for (int i = 0; i < n; ++i) {
        x[i] += step[i];
        if (!sewing) projectOutOfSurfaces(surfaces, x[i]);
      }
      if (joined) seams.average(x);
      disp.swap(step);
      ++iterations;
      const bool converged = max_disp < settings.displacement_tolerance * b &&
                             max_force <= settings.force_tolerance * force_ref;
      const bool stopped = stop();
      if (it % settings.progress_interval == 0 || converged || stopped || it == max_iterations) {
        ProgressEvent e;
        e.load_step = load_step;
        e.load_factor = sewing ? 0.0 : 1.0;
        e.iteration = iterations;
        e.residual = max_disp / b;
        e.active_contacts = active_contacts;
        e.total_iterations = iterations;
        history.push_back(e);
        if (progress) progress(e);
      }
      if (stopped) return Outcome::kStopped;
      if (converged) return Outcome::kConverged;
    }
    return Outcome::kLimit;
  }
};
}  // namespace

DrapeResult solveParticleStatic(const DrapeProblem& problem, const ParticleSettings& settings,
                                const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  problem.validate();
  problem.checkStaticSupport();
  const int n = problem.mesh.numVertices();
  validateSettings(settings, n);
  const ParticleNetwork network(problem.mesh, problem.material, problem.bc.clamped,
                                settings.network);
  const ParticleLoads loads(problem, network);
  // The problem's seams (a scene's) and the settings' (a caller's) are sewn alike.
  std::vector<Seam> all_seams = problem.seams;
  all_seams.insert(all_seams.end(), settings.seams.begin(), settings.seams.end());
  const SeamGroups seams(n, all_seams);

  const double b = network.referenceEdgeLength();
  const auto bound = network.stiffnessBound();
  const double k_max = *std::max_element(bound.begin(), bound.end());
  const double c_disp = settings.c_disp > 0.0 ? settings.c_disp : 1.0 / k_max;
  const double beta = settings.c_acc > 0.0 ? settings.c_acc * c_disp : settings.momentum;
  if (beta >= 1.0) {
    std::ostringstream s;
    s << "particle settings: C_acc C_disp = " << beta
      << " must be below 1, or the pseudo-load grows without bound";
    throw InputError(s.str());
  }

  Relaxation r(network, loads, seams, problem.colliders, settings, progress,
               freeAxes(problem.bc, n), b);
  r.x = settings.initial_positions.empty() ? problem.mesh.vertices : settings.initial_positions;
  r.disp.assign(n, Vec3::Zero());
  std::ostringstream status;
  DrapeResult result;

  auto finish = [&](bool converged) {
    result.converged = converged;
    result.status = status.str();
    result.positions = r.x;
    result.iterations = r.iterations;
    result.residual = r.max_disp / b;
    result.history = r.history;
    for (int i = 0; i < n; ++i)
      if (r.contact_surface.size() == static_cast<std::size_t>(n) && r.contact_surface[i] >= 0)
        result.reactions.push_back({i, r.contact_surface[i], r.reaction[i]});
    result.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  };

  if (!seams.empty()) {
    // Sewing springs default to the mean edge stiffness: strong enough to close the seam
    // against the cloth, soft enough not to shrink the stable step much.
    double k_sew = settings.sewing_stiffness;
    if (k_sew == 0.0) {
      for (const auto& s : network.stretchSprings()) k_sew += s.stiffness;
      k_sew /= network.stretchSprings().size();
    }
    const double c_sew = settings.c_disp > 0.0 ? settings.c_disp : 1.0 / (k_max + 2.0 * k_sew);
    const double join = settings.seam_join_distance > 0.0 ? settings.seam_join_distance : 1e-3 * b;
    const auto outcome =
        r.run(true, c_sew, beta, k_sew, k_sew * seams.maxGap(r.x), settings.max_sewing_iterations,
              0, [&] { return seams.maxGap(r.x) < join; });
    if (outcome == Relaxation::Outcome::kCancelled) {
      result.cancelled = true;
      status << "cancelled while sewing after " << r.iterations
             << " iterations; returning the current state";
      return finish(false);
    }
    if (outcome == Relaxation::Outcome::kNonFinite) {
      status << "sewing diverged (non-finite displacement) after " << r.iterations
             << " iterations; returning the last finite state";
      return finish(false);
    }
    status << "seams " << (outcome == Relaxation::Outcome::kStopped ? "met" : "did not meet")
           << " after " << r.iterations << " sewing iterations (largest gap " << seams.maxGap(r.x)
           << "), joined; ";
    seams.average(r.x);
    std::fill(r.disp.begin(), r.disp.end(), Vec3::Zero());
  }

  // A sewn group moves as one: it is held along an axis if any member is.
  for (const auto& g : seams.groups()) {
    Vec3 m = Vec3::Ones();
    for (int v : g) m = m.cwiseProduct(r.mask[v]);
    for (int v : g) r.mask[v] = m;
  }
  const int sewing_iterations = r.iterations;
  double force_ref = loads.referenceForce();
  if (force_ref == 0.0) force_ref = k_max * b;  // unloaded: any stiffness-sized scale
  const auto outcome =
      r.run(false, c_disp, beta, 0.0, force_ref, settings.max_iterations, 1, [] { return false; });
  result.load_steps = 1;
  result.load_factor = 1.0;
  const int drape_iterations = r.iterations - sewing_iterations;
  switch (outcome) {
    case Relaxation::Outcome::kConverged:
      status << "converged in " << drape_iterations << " iterations";
      break;
    case Relaxation::Outcome::kLimit:
      status << "not converged: iteration limit " << settings.max_iterations << " reached";
      break;
    case Relaxation::Outcome::kCancelled:
      result.cancelled = true;
      status << "cancelled after " << drape_iterations
             << " iterations; returning the current state";
      break;
    default:
      status << "diverged (non-finite displacement) after " << r.iterations
             << " iterations; returning the last finite state";
  }
  status << " (max displacement " << r.max_disp / b << " b, unbalanced force "
         << r.max_force / force_ref << " x reference, C_disp " << c_disp << ", momentum " << beta
         << ")";
  return finish(outcome == Relaxation::Outcome::kConverged);
}

}  // namespace chs
