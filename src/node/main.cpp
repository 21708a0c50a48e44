#include <ros/ros.h>

#include "cloth_hair_sim/node/sim_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "cloth_hair_sim_node");
  ros::NodeHandle nh, pnh("~");
  std::unique_ptr<chs_node::SimNode> node;
  try {
    node = std::make_unique<chs_node::SimNode>(nh, pnh);
  } catch (const std::exception& e) {
    ROS_FATAL("cloth_hair_sim_node: %s", e.what());
    return 1;
  }
  // Several threads: a long ~drape_solve must not stall the timers and the other services.
  ros::AsyncSpinner spinner(4);
  spinner.start();
  ros::waitForShutdown();
  return 0;
}
