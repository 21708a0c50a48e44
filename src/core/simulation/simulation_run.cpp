#include "cloth_hair_sim/core/simulation/simulation_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

SimulationRun::SimulationRun(const SimulationScene& scene, int max_halvings)
    : scene_(scene), max_halvings_(max_halvings), world_(scene.world) {
  for (const SimulationBody& b : scene_.bodies) {
    HybridShellSettings settings = scene_.shell;
    // A world without its own spacing takes the first body's: build the others on it.
    settings.grid_spacing = world_.gridSpacing();
    std::shared_ptr<HybridShellDynamics> d;
    try {
      d = std::make_shared<HybridShellDynamics>(b.problem, settings);
    } catch (const InputError& e) {
      throw InputError("body " + b.name + ": " + e.what());
    }
    std::vector<Eigen::Vector3d> v(d->numVertices(), b.velocity);
    for (int i = 0; i < d->numVertices(); ++i)
      if (d->isPinned(i)) v[i].setZero();
    d->setVelocities(v);
    world_.add(b.name, d);
    bodies_.push_back(d);

    std::set<std::array<int, 2>> edges;
    for (const auto& q : b.problem.mesh.quads)
      for (int k = 0; k < 4; ++k)
        edges.insert({std::min(q[k], q[(k + 1) % 4]), std::max(q[k], q[(k + 1) % 4])});
    edges_.emplace_back(edges.begin(), edges.end());
    vertex_stencils_.push_back(vertexStencils(b.problem.mesh, d->limitSurface()));
    const std::vector<Eigen::Vector3d> rest = evaluate(vertex_stencils_.back(), d->positions());
    rest_lengths_.emplace_back();
    for (const auto& e : edges_.back())
      rest_lengths_.back().push_back((rest[e[1]] - rest[e[0]]).norm());
  }
  for (const SimulationHair& h : scene_.hair) {
    rod::HairSettings settings;
    settings.grid_spacing = world_.gridSpacing() > 0.0 ? world_.gridSpacing() : 0.01;
    settings.kernel_degree = scene_.world.kernel_degree;
    settings.gravity = scene_.gravity;
    settings.pic_blend = h.pic_blend;
    settings.continuum = h.continuum;
    std::shared_ptr<rod::HairDynamics> d;
    try {
      d = std::make_shared<rod::HairDynamics>(settings);
      for (const auto& strand : h.strands) d->addStrand(strand, h.material, h.roots != "loose");
    } catch (const InputError& e) {
      throw InputError("hair " + h.name + ": " + e.what());
    }
    world_.add(h.name, d);
    hair_.push_back(d);
  }
  placeColliders(0.0, 0.0);
}

void SimulationRun::placeRoots(double t) {
  for (std::size_t k = 0; k < hair_.size(); ++k) {
    const SimulationHair& h = scene_.hair[k];
    if (h.root_collider < 0) continue;
    const SimulationCollider& c = scene_.colliders[h.root_collider];
    const Eigen::Isometry3d motion = c.poseAt(t) * c.pose.inverse();
    for (int s = 0; s < hair_[k]->numStrands(); ++s) hair_[k]->setRootFrame(s, motion);
  }
}

std::vector<Eigen::Isometry3d> SimulationRun::colliderPoses() const {
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& c : scene_.colliders) poses.push_back(c.poseAt(world_.time()));
  return poses;
}

void SimulationRun::placeColliders(double t0, double t1) {
  RigidSurfaces surfaces;
  std::vector<SurfaceVelocity> velocities;
  std::vector<double> frictions;
  for (const auto& c : scene_.colliders) {
    surfaces.push_back(c.surfaceAt(t1));
    velocities.push_back(c.motion.velocity(c.pose, t0, t1));
    frictions.push_back(c.friction);
  }
  world_.setColliders(surfaces, velocities, frictions);
}

bool SimulationRun::diverged(const WorldStepReport& report) const {
  if (!report.diverged.empty()) return true;
  for (const auto& b : bodies_)
    if (!std::isfinite(b->kineticEnergy())) return true;
  for (const auto& h : hair_)
    if (!std::isfinite(h->kineticEnergy())) return true;
  return false;
}

bool SimulationRun::guardedStep(double dt, int depth, FrameRecord& rec,
                                std::vector<ColliderLoad>& load_sum) {
  const World::Snapshot before = world_.snapshot();
  const double t0 = world_.time();
  bool moving = false;
  for (const auto& c : scene_.colliders) moving = moving || c.motion.moves();
  if (moving) {
    placeColliders(t0, t0 + dt);
    placeRoots(t0 + dt);
  }
  const WorldStepReport report = world_.step(dt);
  ++rec.substeps;
  if (!diverged(report)) {
    if (!report.converged) ++rec.unconverged;
    const std::vector<ColliderLoad> loads = world_.colliderLoads();
    for (std::size_t i = 0; i < loads.size(); ++i) {
      load_sum[i].force += dt * loads[i].force;
      load_sum[i].moment += dt * loads[i].moment;
    }
    return true;
  }
  world_.restore(before);
  ++rec.rollbacks;
  if (depth <= 0) return false;
  return guardedStep(0.5 * dt, depth - 1, rec, load_sum) &&
         guardedStep(0.5 * dt, depth - 1, rec, load_sum);
}

FrameRecord SimulationRun::record() const {
  FrameRecord rec;
  rec.frame = frames_done_;
  rec.time = world_.time();
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const HybridShellDynamics& d = *bodies_[b];
    BodyFrame f;
    f.kinetic_energy = d.kineticEnergy();
    f.deepest_penetration = d.deepestPenetration();
    const std::vector<Eigen::Vector3d> x = evaluate(vertex_stencils_[b], d.positions());
    for (std::size_t e = 0; e < edges_[b].size(); ++e) {
      const auto& ends = edges_[b][e];
      f.largest_stretch =
          std::max(f.largest_stretch, (x[ends[1]] - x[ends[0]]).norm() / rest_lengths_[b][e]);
    }
    rec.kinetic_energy += f.kinetic_energy;
    rec.bodies.push_back(f);
  }
  std::vector<std::shared_ptr<const RigidSurface>> surfaces;
  const std::vector<Eigen::Isometry3d> poses = colliderPoses();
  if (!hair_.empty())
    for (std::size_t c = 0; c < scene_.colliders.size(); ++c)
      surfaces.push_back(scene_.colliders[c].shape.makeSurface(poses[c]));
  for (const auto& h : hair_) {
    BodyFrame f;
    f.kinetic_energy = h->kineticEnergy();
    for (int s = 0; s < h->numStrands(); ++s) {
      const rod::DiscreteElasticRod& rod = h->strand(s);
      const auto& x = rod.positions();
      for (int j = 0; j < rod.numEdges(); ++j)
        f.largest_stretch =
            std::max(f.largest_stretch, (x[j + 1] - x[j]).norm() / rod.restLength(j));
      for (const auto& surface : surfaces)
        for (const auto& p : x)
          f.deepest_penetration = std::max(f.deepest_penetration, -surface->project(p).gap);
    }
    rec.kinetic_energy += f.kinetic_energy;
    rec.bodies.push_back(f);
  }
  rec.collider_loads.assign(scene_.colliders.size(), ColliderLoad());
  return rec;
}

FrameRecord SimulationRun::advanceFrame() {
  if (finished()) throw std::logic_error("SimulationRun::advanceFrame: the run is over");
  const auto start = std::chrono::steady_clock::now();
  const int frame = frames_done_ + 1;
  const double frame_start = world_.time();
  const double end = std::min(frame / scene_.frame_rate, scene_.duration);
  FrameRecord rec;
  std::vector<ColliderLoad> load_sum(scene_.colliders.size());
  while (world_.time() < end - 1e-12) {
    const double stable = world_.stableTimeStep();
    std::ostringstream why;
    if (!(stable > 0.0) || !std::isfinite(stable)) {
      why << "frame " << frame << ": the stable time step is " << stable
          << " s (the state has blown up)";
    } else if (rec.substeps >= scene_.max_substeps_per_frame) {
      why << "frame " << frame
          << " needs more than max_substeps_per_frame = " << scene_.max_substeps_per_frame
          << " substeps (stable step " << stable << " s)";
    } else {
      const double dt = std::min(stable, end - world_.time());
      if (guardedStep(dt, max_halvings_, rec, load_sum)) continue;
      why << "frame " << frame << ": the step of " << dt << " s at t = " << world_.time()
          << " s diverged, and so did its halves down to " << dt / std::pow(2.0, max_halvings_)
          << " s";
    }
    stop_reason_ = why.str();
    break;
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!stopped()) ++frames_done_;
  FrameRecord out = record();
  out.frame = frame;
  out.wall_time_s = wall;
  out.substeps = rec.substeps;
  out.rollbacks = rec.rollbacks;
  out.unconverged = rec.unconverged;
  const double span = world_.time() - frame_start;
  const std::vector<Eigen::Isometry3d> poses = colliderPoses();
  for (std::size_t i = 0; i < load_sum.size() && span > 0.0; ++i) {
    ColliderLoad mean;
    mean.force = load_sum[i].force / span;
    mean.moment = load_sum[i].moment / span;
    out.collider_loads[i].force = mean.force;
    out.collider_loads[i].moment = mean.momentAbout(poses[i].translation());
  }
  return out;
}

}  // namespace chs
