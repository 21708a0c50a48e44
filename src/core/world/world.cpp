#include "cloth_hair_sim/core/world/world.h"

#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/common/names.h"
#include "cloth_hair_sim/core/mesh/scene_scale.h"

namespace chs {

namespace {

// A grid cell finer than the finest cloth cell a scene may hold, or coarser than a metre (no
// contact between garments could be resolved on it), is a unit or typing mistake.
constexpr double kMaxGridSpacing = 1.0;

void checkSpacing(const std::string& who, double dx) {
  if (!(dx >= kMinCellEdge && dx <= kMaxGridSpacing))
    throw InputError(who + "grid spacing " + std::to_string(dx) + " m lies outside " +
                     std::to_string(kMinCellEdge) + " m to " + std::to_string(kMaxGridSpacing) +
                     " m");
}

}  // namespace

World::World(const WorldSettings& settings) : settings_(settings) {
  if (!std::isfinite(settings.grid_spacing)) throw InputError("world: grid_spacing must be finite");
  if (settings.kernel_degree != 2 && settings.kernel_degree != 3)
    throw InputError("world: kernel_degree must be 2 or 3, got " +
                     std::to_string(settings.kernel_degree));
  if (!(settings.body_friction >= 0.0) || !std::isfinite(settings.body_friction))
    throw InputError("world: body_friction must be >= 0");
  if (!std::isfinite(settings.contact_distance))
    throw InputError("world: contact_distance must be finite");
  if (!(settings.cfl > 0.0 && settings.cfl <= 1.0))
    throw InputError("world: cfl must lie in (0, 1]");
  if (settings.max_particles < 1)
    throw InputError("world: max_particles must be at least 1, got " +
                     std::to_string(settings.max_particles));
  if (settings.grid_spacing > 0.0) checkSpacing("world: ", settings.grid_spacing);
  spacing_ = settings.grid_spacing > 0.0 ? settings.grid_spacing : 0.0;
}

double World::gridSpacing() const {
  return spacing_;
}

Body& World::add(const std::string& name, std::shared_ptr<Body> body) {
  const std::string who = "world: body '" + name + "': ";
  try {
    checkName(name);
  } catch (const InputError& e) {
    throw InputError(who + e.what());
  }
  if (!body) throw InputError(who + "is null");
  for (const Entry& e : bodies_)
    if (e.name == name) throw InputError(who + "a body of that name is in the world");
  const double dx = body->field().spacing();
  checkSpacing(who, dx);
  if (spacing_ > 0.0 && std::abs(dx - spacing_) > 1e-12 * spacing_)
    throw InputError(who + "its grid spacing " + std::to_string(dx) + " m is not the world's " +
                     std::to_string(spacing_) + " m (build it with the world's gridSpacing())");
  if (body->kernelDegree() != settings_.kernel_degree)
    throw InputError(who + "its kernel degree " + std::to_string(body->kernelDegree()) +
                     " is not the world's " + std::to_string(settings_.kernel_degree));
  const long particles = static_cast<long>(body->motion().x.size()), held = numParticles();
  if (particles > settings_.max_particles - held)
    throw InputError(who + "its " + std::to_string(particles) +
                     " particles would bring the world to " + std::to_string(held + particles) +
                     ", over max_particles " + std::to_string(settings_.max_particles) +
                     " (WorldSettings::max_particles; coarsen it or remove a body)");
  body->setColliders(colliders_, collider_velocities_, collider_frictions_);
  if (spacing_ <= 0.0) spacing_ = dx;
  bodies_.push_back({name, std::move(body)});
  return *bodies_.back().body;
}

long World::numParticles() const {
  long n = 0;
  for (const Entry& e : bodies_) n += static_cast<long>(e.body->motion().x.size());
  return n;
}

bool World::remove(const std::string& name) {
  for (auto it = bodies_.begin(); it != bodies_.end(); ++it)
    if (it->name == name) {
      bodies_.erase(it);
      if (bodies_.empty() && settings_.grid_spacing <= 0.0) spacing_ = 0.0;
      return true;
    }
  return false;
}

Body* World::find(const std::string& name) {
  for (Entry& e : bodies_)
    if (e.name == name) return e.body.get();
  return nullptr;
}

void World::setColliders(const RigidSurfaces& colliders,
                         const std::vector<SurfaceVelocity>& velocities,
                         const std::vector<double>& frictions) {
  // Every body checks the lists the same way; the first refuses before anything changed.
  for (Entry& e : bodies_) e.body->setColliders(colliders, velocities, frictions);
  colliders_ = colliders;
  collider_velocities_ = velocities;
  collider_frictions_ = frictions;
}

double World::stableTimeStep() const {
  double h = std::numeric_limits<double>::max();
  for (const Entry& e : bodies_) h = std::min(h, e.body->stableTimeStep());
  if (bodies_.size() < 2) return h;
  std::vector<mpm::MotionGroup> groups;
  for (const Entry& e : bodies_) {
    groups.push_back(e.body->motion());
    groups.back().self = false;  // each body's own bound holds its approach on itself
  }
  const double dx = gridSpacing();
  return mpm::motionTimeStep(groups, {}, (settings_.kernel_degree + 1) * dx, settings_.cfl * dx, h);
}

// The bodies' own stages run side by side, a body to a task (each body's loops nest inside its
// task): a body's stage touches only its own model, state and field, and reads the colliders.
// Many small garments otherwise run one after the other, each stage a parallel loop of a few
// hundred items whose threads spend more time waking and sleeping than working. The contact
// between fields joins them between the stages.
void World::forEachBody(const std::function<void(Entry&)>& stage) {
  if (bodies_.size() < 2) {
    for (Entry& e : bodies_) stage(e);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, bodies_.size(), 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t b = r.begin(); b != r.end(); ++b) stage(bodies_[b]);
                    });
}

WorldStepReport World::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw InputError("world: time step must be positive, got " + std::to_string(dt));
  WorldStepReport report;
  forEachBody([dt](Entry& e) { e.body->beginStep(dt); });
  forEachBody([](Entry& e) { e.body->transferToGrid(); });
  std::vector<char> converged(bodies_.size(), 1);
  forEachBody([&](Entry& e) { converged[&e - bodies_.data()] = e.body->updateGrid(dt); });
  for (std::size_t b = 0; b < bodies_.size(); ++b)
    if (!converged[b]) {
      report.converged = false;
      report.unconverged.push_back(bodies_[b].name);
    }
  if (bodies_.size() > 1) {
    std::vector<ContactField> fields(bodies_.size());
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      fields[b].grid = &bodies_[b].body->field();
      fields[b].carriers = bodies_[b].body->fieldCarriers();
      const Body* body = bodies_[b].body.get();
      fields[b].normals = [body](std::vector<Eigen::Vector3d>& n) { body->fieldNormals(n); };
    }
    FieldContactSettings contact{settings_.body_friction, settings_.contact_distance};
    if (contact.contact_distance <= 0.0) contact.contact_distance = 0.25 * spacing_;
    std::vector<char> touched;
    report.contact = resolveFieldContact(fields, settings_.kernel_degree, dt, contact, &touched);
    for (std::size_t b = 0; b < bodies_.size(); ++b)
      if (touched[b]) bodies_[b].body->reapplyColliders();
  }
  forEachBody([dt](Entry& e) { e.body->transferFromGrid(dt); });
  forEachBody([dt](Entry& e) { e.body->endStep(dt); });
  for (const Entry& e : bodies_)
    if (!e.body->finite()) report.diverged.push_back(e.name);
  time_ += dt;
  last_dt_ = dt;
  return report;
}

std::vector<ColliderLoad> World::colliderLoads() const {
  std::vector<ColliderLoad> loads(colliders_.size());
  if (last_dt_ <= 0.0) return loads;
  for (const Entry& e : bodies_) {
    const auto& impulses = e.body->colliderImpulses();
    for (std::size_t c = 0; c < impulses.size() && c < loads.size(); ++c) {
      loads[c].force -= impulses[c].linear / last_dt_;
      loads[c].moment -= impulses[c].angular / last_dt_;
    }
  }
  return loads;
}

World::Snapshot World::snapshot() const {
  Snapshot s;
  s.time = time_;
  for (const Entry& e : bodies_) {
    s.names.push_back(e.name);
    s.bodies.push_back(e.body->snapshot());
  }
  return s;
}

void World::restore(const Snapshot& s) {
  if (s.names.size() != bodies_.size())
    throw InputError("world: the snapshot holds " + std::to_string(s.names.size()) +
                     " bodies, the world " + std::to_string(bodies_.size()));
  for (std::size_t b = 0; b < bodies_.size(); ++b)
    if (s.names[b] != bodies_[b].name)
      throw InputError("world: the snapshot's body " + std::to_string(b) + " is '" + s.names[b] +
                       "', the world's '" + bodies_[b].name + "'");
  for (std::size_t b = 0; b < bodies_.size(); ++b) bodies_[b].body->restore(*s.bodies[b]);
  time_ = s.time;
}

}  // namespace chs
