#include "cloth_hair_sim/node/sim_node.h"

#include <algorithm>
#include <cmath>

#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/MarkerArray.h>

#include "cloth_hair_sim/SimStatus.h"
#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "cloth_hair_sim/node/markers.h"

namespace chs_node {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::vector<TrackedCollider> collidersParam(const ros::NodeHandle& pnh) {
  XmlRpc::XmlRpcValue list;
  if (!pnh.getParam("colliders", list)) return {};
  return parseColliders(list);
}

}  // namespace

SimNode::SimNode(ros::NodeHandle nh, ros::NodeHandle private_nh)
    : nh_(nh),
      pnh_(private_nh),
      params_(loadSimParams(private_nh)),
      tf_listener_(tf_buffer_),
      colliders_(tf_buffer_, params_.world_frame, params_.tf_timeout) {
  dynamics_settings_.damping = params_.damping;
  colliders_.setColliders(collidersParam(pnh_));

  status_pub_ = pnh_.advertise<cloth_hair_sim::SimStatus>("status", 10);
  marker_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>("markers", 1);
  load_srv_ = pnh_.advertiseService("load_garment", &SimNode::loadGarment, this);
  remove_srv_ = pnh_.advertiseService("remove_garment", &SimNode::removeGarment, this);
  list_srv_ = pnh_.advertiseService("list_garments", &SimNode::listGarments, this);
  reset_srv_ = pnh_.advertiseService("reset", &SimNode::reset, this);
  pause_srv_ = pnh_.advertiseService("pause", &SimNode::pause, this);
  step_srv_ = pnh_.advertiseService("step", &SimNode::step, this);
  drape_srv_ = pnh_.advertiseService("drape_solve", &SimNode::drapeSolve, this);
  step_timer_ =
      nh_.createTimer(ros::Duration(1.0 / params_.step_rate), &SimNode::onStepTimer, this);
  status_timer_ =
      nh_.createTimer(ros::Duration(1.0 / params_.status_rate), &SimNode::onStatusTimer, this);
  marker_timer_ =
      nh_.createTimer(ros::Duration(1.0 / params_.marker_rate), &SimNode::onMarkerTimer, this);
  ROS_INFO(
      "cloth_hair_sim_node: world frame '%s', %zu colliders, backend %s, dt %g s, %g Hz, "
      "real-time factor %g",
      params_.world_frame.c_str(), colliders_.colliders().size(), params_.dynamics_backend.c_str(),
      params_.dt, params_.step_rate, params_.real_time_factor);
}

void SimNode::refreshColliders() {
  transforms_ok_ = colliders_.update();
  if (!transforms_ok_)
    ROS_WARN_THROTTLE(5.0, "colliders without a transform to '%s' hold their last pose: %s",
                      params_.world_frame.c_str(), joined(colliders_.staleNames()).c_str());
  chs::RigidSurfaces surfaces;
  try {
    surfaces = colliders_.surfaces();
  } catch (const std::exception& e) {  // a degenerate transform: keep the previous surfaces
    ROS_ERROR_THROTTLE(5.0, "colliders not updated: %s", e.what());
    return;
  }
  for (auto& [name, g] : garments_) g.dynamics->setColliders(surfaces);
}

double SimNode::substepLimit() const {
  double h = params_.dt;
  for (const auto& [name, g] : garments_) h = std::min(h, g.stable_dt);
  return h;
}

bool SimNode::diverged(const Garment& g) const {
  const auto& x = g.dynamics->positions();
  const auto& v = g.dynamics->velocities();
  for (size_t i = 0; i < x.size(); ++i)
    if (!x[i].allFinite() || !v[i].allFinite() || v[i].norm() > params_.max_speed) return true;
  return false;
}

void SimNode::stepGarment(Garment& g, double h, int depth) {
  const std::vector<Eigen::Vector3d> x = g.dynamics->positions(), v = g.dynamics->velocities();
  g.dynamics->step(h);
  if (!diverged(g)) return;
  g.dynamics->setPositions(x);
  g.dynamics->setVelocities(v);
  ++rollbacks_;
  if (depth < 4) {
    stepGarment(g, 0.5 * h, depth + 1);
    stepGarment(g, 0.5 * h, depth + 1);
    return;
  }
  // Still diverging at a sixteenth of the step: stop the garment where it was rather than
  // publish garbage; the node carries on.
  g.dynamics->setVelocities(std::vector<Eigen::Vector3d>(v.size(), Eigen::Vector3d::Zero()));
  ROS_ERROR_THROTTLE(5.0, "garment '%s' diverges even at dt %g s: stopped in place", g.name.c_str(),
                     h);
}

void SimNode::advance(int count, double h) {
  for (int i = 0; i < count; ++i) {
    for (auto& [name, g] : garments_) stepGarment(g, h, 0);
    sim_time_ += h;
    ++steps_;
  }
}

void SimNode::onStepTimer(const ros::TimerEvent& event) {
  std::lock_guard<std::mutex> lock(mutex_);
  refreshColliders();
  const double period = 1.0 / params_.step_rate;
  double elapsed =
      event.last_real.isZero() ? period : (event.current_real - event.last_real).toSec();
  if (!(elapsed > 0.0)) elapsed = period;
  if (paused_ || garments_.empty()) {  // keeps the substep of the last ~step for the status
    last_.substeps = 0;
    last_.wall_per_step = last_.real_time_factor = 0.0;
    return;
  }
  // After a stall (a slow callback, a paused /clock) do not try to catch up all at once.
  const double budget = std::min(elapsed, 5.0 * period);
  const double h_max = substepLimit();
  int n = params_.max_substeps;
  double h = h_max;
  if (params_.real_time_factor > 0.0) {
    const double target = params_.real_time_factor * budget;
    const double needed = std::ceil(target / h_max - 1e-9);
    if (needed <= params_.max_substeps) {
      n = std::max(1, static_cast<int>(needed));
      h = target / n;
    }
  }
  const Clock::time_point start = Clock::now();
  advance(n, h);
  const double wall = secondsSince(start);
  last_.dt = h;
  last_.substeps = n;
  last_.wall_per_step = wall / n;
  last_.real_time_factor = n * h / std::max(elapsed, wall);
}

void SimNode::onStatusTimer(const ros::TimerEvent&) {
  cloth_hair_sim::SimStatus s;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    s.header.stamp = ros::Time::now();
    s.header.frame_id = params_.world_frame;
    s.state = garments_.empty() ? "idle" : paused_ ? "paused" : "running";
    s.sim_time = sim_time_;
    s.steps = steps_;
    s.dt = last_.dt;
    s.substeps = last_.substeps;
    s.wall_time_per_step = last_.wall_per_step;
    s.real_time_factor = last_.real_time_factor;
    s.garments = static_cast<int>(garments_.size());
    s.colliders = colliders_.activeCount();
    for (const auto& [name, g] : garments_) {
      s.vertices += g.dynamics->numVertices();
      s.kinetic_energy += g.dynamics->kineticEnergy();
      for (const auto& x : g.dynamics->positions())
        for (const auto& c : g.dynamics->colliders())
          s.deepest_penetration = std::max(s.deepest_penetration, -c->project(x).gap);
    }
    s.rollbacks = rollbacks_;
    s.transforms_ok = transforms_ok_;
    s.stale_colliders = colliders_.staleNames();
  }
  s.drape_running = drape_running_;
  status_pub_.publish(s);
}

void SimNode::onMarkerTimer(const ros::TimerEvent&) {
  visualization_msgs::MarkerArray array;
  visualization_msgs::Marker clear;  // removed garments and colliders disappear
  clear.action = visualization_msgs::Marker::DELETEALL;
  array.markers.push_back(clear);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [name, g] : garments_)
      array.markers.push_back(
          garmentMarker(g.reference.mesh, g.dynamics->positions(), g.colour, g.colour));
    if (params_.show_colliders) {
      int id = 0;
      for (const auto& c : colliders_.colliders()) {
        if (c.has_pose) array.markers.push_back(colliderMarker(c, id));
        ++id;
      }
    }
  }
  const ros::Time now = ros::Time::now();
  for (auto& m : array.markers) {
    m.header.stamp = now;
    m.header.frame_id = params_.world_frame;
  }
  marker_pub_.publish(array);
}

bool SimNode::loadGarment(cloth_hair_sim::LoadGarment::Request& req,
                          cloth_hair_sim::LoadGarment::Response& res) {
  res.success = false;
  const std::string who = "garment '" + req.name + "': ";
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (garments_.count(req.name)) {
      res.message = who + "a garment of that name is loaded; remove it first";
      return true;
    }
  }
  Eigen::Isometry3d world_from_frame = Eigen::Isometry3d::Identity();
  if (!req.frame_id.empty() && req.frame_id != params_.world_frame) {
    std::string error;
    if (!tf_buffer_.canTransform(params_.world_frame, req.frame_id, ros::Time(0),
                                 ros::Duration(0.5), &error)) {
      res.message = who + "frame '" + req.frame_id + "' has no transform to '" +
                    params_.world_frame + "' (" + error + ")";
      return true;
    }
    try {
      world_from_frame = tf2::transformToEigen(
          tf_buffer_.lookupTransform(params_.world_frame, req.frame_id, ros::Time(0)));
    } catch (const tf2::TransformException& e) {
      res.message = who + "frame '" + req.frame_id + "': " + e.what();
      return true;
    }
  }
  try {
    Garment g = buildGarment(req, world_from_frame, params_.gravity, dynamics_settings_);
    std::lock_guard<std::mutex> lock(mutex_);
    if (garments_.count(req.name)) {
      res.message = who + "a garment of that name was loaded meanwhile";
      return true;
    }
    g.generation = next_generation_++;
    g.colour = next_colour_++;
    g.dynamics->setColliders(colliders_.surfaces());
    res.vertices = g.reference.mesh.numVertices();
    res.faces = g.reference.mesh.numQuads();
    res.success = true;
    res.message = who + "loaded, " + std::to_string(res.vertices) + " vertices, " +
                  std::to_string(res.faces) + " quads, material " + g.material_name;
    garments_.emplace(req.name, std::move(g));
  } catch (const std::exception& e) {
    res.message = who + e.what();
  }
  if (res.success)
    ROS_INFO("%s", res.message.c_str());
  else
    ROS_WARN("%s", res.message.c_str());
  return true;
}

bool SimNode::removeGarment(cloth_hair_sim::RemoveGarment::Request& req,
                            cloth_hair_sim::RemoveGarment::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  res.success = garments_.erase(req.name) > 0;
  res.message = "garment '" + req.name + "': " + (res.success ? "removed" : "not loaded");
  return true;
}

bool SimNode::listGarments(cloth_hair_sim::ListGarments::Request&,
                           cloth_hair_sim::ListGarments::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [name, g] : garments_) {
    res.names.push_back(name);
    res.vertices.push_back(g.dynamics->numVertices());
    res.materials.push_back(g.material_name);
  }
  return true;
}

bool SimNode::reset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  try {
    for (auto& [name, g] : garments_) {
      resetDynamics(g, dynamics_settings_);
      g.generation = next_generation_++;
      g.dynamics->setColliders(colliders_.surfaces());
    }
  } catch (const std::exception& e) {
    res.success = false;
    res.message = e.what();
    return true;
  }
  sim_time_ = 0.0;
  steps_ = 0;
  rollbacks_ = 0;
  last_ = UpdateStats();
  res.success = true;
  res.message = "reset " + std::to_string(garments_.size()) + " garments to their reference";
  return true;
}

bool SimNode::pause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  paused_ = req.data;
  res.success = true;
  res.message = paused_ ? "paused" : "running";
  return true;
}

bool SimNode::step(cloth_hair_sim::StepSim::Request& req, cloth_hair_sim::StepSim::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  res.success = false;
  if (!paused_) {
    res.message = "the simulation is running: pause it first (~pause true)";
  } else if (req.steps < 1 || req.steps > 1000000) {
    res.message = "steps must be between 1 and 1000000";
  } else {
    refreshColliders();
    const double h = substepLimit();
    advance(req.steps, h);
    last_ = UpdateStats();
    last_.dt = h;
    last_.substeps = req.steps;
    res.success = true;
    res.message =
        "advanced " + std::to_string(req.steps) + " substeps of " + std::to_string(h) + " s";
  }
  res.sim_time = sim_time_;
  return true;
}

bool SimNode::drapeSolve(cloth_hair_sim::DrapeSolve::Request& req,
                         cloth_hair_sim::DrapeSolve::Response& res) {
  res.success = res.converged = false;
  const std::string who = "drape of '" + req.garment + "': ";
  if (drape_running_.exchange(true)) {
    res.message = who + "another drape solve is running; try again when it is done";
    return true;
  }
  struct Release {
    std::atomic<bool>& flag;
    ~Release() { flag = false; }
  } release{drape_running_};

  chs::DrapeProblem problem;
  std::uint64_t generation = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = garments_.find(req.garment);
    if (it == garments_.end()) {
      res.message = who + "no garment of that name is loaded";
      return true;
    }
    problem = it->second.reference;
    problem.colliders = colliders_.surfaces();
    generation = it->second.generation;
  }
  const Clock::time_point start = Clock::now();
  try {
    const chs::DrapeMethod method = chs::parseMethod(req.method.empty() ? "fem_shell" : req.method);
    if (!(req.tolerance >= 0.0) || !std::isfinite(req.tolerance))
      throw chs::InputError("tolerance must be >= 0 (0: the solver's default)");
    if (req.max_iterations < 0) throw chs::InputError("max_iterations must be >= 0 (0: default)");
    if (!(req.stabilization >= 0.0) || !std::isfinite(req.stabilization))
      throw chs::InputError("stabilization must be >= 0");
    problem.checkStaticSupport();
    chs::DrapeResult r;
    if (method == chs::DrapeMethod::kFemShell) {
      chs::FemShellSettings s;
      if (req.tolerance > 0.0) s.tolerance = req.tolerance;
      if (req.max_iterations > 0) s.max_load_steps = req.max_iterations;
      s.stabilization = req.stabilization;
      r = chs::solveFemShell(problem, s);
    } else {
      chs::ParticleSettings s;
      if (req.tolerance > 0.0) s.displacement_tolerance = req.tolerance;
      if (req.max_iterations > 0) s.max_iterations = req.max_iterations;
      r = chs::solveParticleStatic(problem, s);
    }
    res.converged = r.converged;
    res.iterations = r.iterations;
    res.residual = r.residual;
    res.message = who + r.status;
    const bool complete = static_cast<int>(r.positions.size()) == problem.mesh.numVertices() &&
                          std::all_of(r.positions.begin(), r.positions.end(),
                                      [](const Eigen::Vector3d& x) { return x.allFinite(); });
    if (complete) res.mesh = meshMessage(problem.mesh, r.positions);
    if (r.converged && complete) {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto it = garments_.find(req.garment);
      if (it == garments_.end() || it->second.generation != generation) {
        res.message += "; not applied: the garment was removed, reloaded or reset meanwhile";
      } else {
        it->second.dynamics->setPositions(r.positions);
        it->second.dynamics->setVelocities(
            std::vector<Eigen::Vector3d>(r.positions.size(), Eigen::Vector3d::Zero()));
        res.success = true;
      }
    }
  } catch (const std::exception& e) {
    res.message = who + e.what();
  }
  res.wall_time = secondsSince(start);
  ROS_INFO("%s (%.2f s)", res.message.c_str(), res.wall_time);
  return true;
}

}  // namespace chs_node
