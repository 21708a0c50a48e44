#pragma once
#include <functional>

#include <actionlib/server/simple_action_server.h>
#include <ros/node_handle.h>

#include "cloth_hair_sim/DrapeSolve.h"
#include "cloth_hair_sim/DrapeSolveAction.h"
#include "cloth_hair_sim/core/common/cancel_flag.h"
#include "cloth_hair_sim/core/drape/drape_problem.h"

namespace chs_node {

// The ~drape action server. Each goal runs on actionlib's own thread through `solve` (the code
// behind ~drape_solve); the solver's progress goes out as feedback, and a cancel, or a newer
// goal, asks the solver to stop at its next iteration.
class DrapeAction {
 public:
  // Runs the drape of req into res; returns true when the solve stopped because cancel was set.
  using Solve = std::function<bool(
      const cloth_hair_sim::DrapeSolve::Request& req, cloth_hair_sim::DrapeSolve::Response& res,
      const chs::ProgressCallback& progress, const chs::CancelFlag* cancel)>;

  DrapeAction(ros::NodeHandle private_nh, Solve solve);
  // Cancels a running solve: the server's destructor waits for its thread.
  ~DrapeAction();

 private:
  void execute(const cloth_hair_sim::DrapeSolveGoalConstPtr& goal);

  Solve solve_;
  chs::CancelFlag cancel_{false};
  actionlib::SimpleActionServer<cloth_hair_sim::DrapeSolveAction> server_;
};

}  // namespace chs_node
