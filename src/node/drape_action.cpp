#include "cloth_hair_sim/node/drape_action.h"

#include <chrono>

namespace chs_node {
namespace {

// Feedback at most this often [s]: the particle solver reports every thousand iterations, which
// on a small garment is hundreds of times a second.
constexpr double kFeedbackPeriod = 0.05;

}  // namespace

DrapeAction::DrapeAction(ros::NodeHandle private_nh, Solve solve)
    : solve_(std::move(solve)),
      server_(
          private_nh, "drape",
          [this](const cloth_hair_sim::DrapeSolveGoalConstPtr& goal) { execute(goal); }, false) {
  server_.registerPreemptCallback([this] { cancel_ = true; });
  server_.start();
}

DrapeAction::~DrapeAction() {
  cancel_ = true;
}

void DrapeAction::execute(const cloth_hair_sim::DrapeSolveGoalConstPtr& goal) {
  // A cancel that came before this line has already set the preempt request.
  cancel_ = server_.isPreemptRequested();
  cloth_hair_sim::DrapeSolve::Request req;
  req.garment = goal->garment;
  req.method = goal->method;
  req.tolerance = goal->tolerance;
  req.max_iterations = goal->max_iterations;
  req.stabilization = goal->stabilization;
  req.scheme = goal->scheme;
  req.adaptive_levels = goal->adaptive_levels;
  req.coarse_levels = goal->coarse_levels;

  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  Clock::time_point last_feedback;
  bool any_feedback = false;
  const auto progress = [&](const chs::ProgressEvent& e) {
    const Clock::time_point now = Clock::now();
    if (any_feedback &&
        std::chrono::duration<double>(now - last_feedback).count() < kFeedbackPeriod)
      return;
    any_feedback = true;
    last_feedback = now;
    cloth_hair_sim::DrapeSolveFeedback f;
    f.load_step = e.load_step;
    f.load_factor = e.load_factor;
    f.iteration = e.iteration;
    f.total_iterations = e.total_iterations;
    f.coarser_grids = e.coarser_grids;
    f.residual = e.residual;
    f.active_contacts = e.active_contacts;
    f.elapsed = std::chrono::duration<double>(now - start).count();
    server_.publishFeedback(f);
  };

  cloth_hair_sim::DrapeSolve::Response res;
  const bool cancelled = solve_(req, res, progress, &cancel_);
  cloth_hair_sim::DrapeSolveResult result;
  result.success = res.success;
  result.converged = res.converged;
  result.cancelled = cancelled;
  result.iterations = res.iterations;
  result.residual = res.residual;
  result.wall_time = res.wall_time;
  result.message = res.message;
  result.mesh = res.mesh;
  if (res.success)
    server_.setSucceeded(result, res.message);
  else if (cancelled)
    server_.setPreempted(result, res.message);
  else
    server_.setAborted(result, res.message);
}

}  // namespace chs_node
