// mannequin_animator: publishes sensor_msgs/JointState of a simple motion of urdf/mannequin.urdf
// (~motion: still | arms_raise | walk, ~period [s], ~rate [Hz], ~start_delay [s]) so that
// robot_state_publisher moves the skeleton and the simulator's URDF colliders follow it.
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>

#include "cloth_hair_sim/node/animator.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "mannequin_animator");
  ros::NodeHandle nh, pnh("~");
  std::string motion_name = "arms_raise";
  double period = 6.0, rate = 50.0, start_delay = 2.0;
  pnh.param("motion", motion_name, motion_name);
  pnh.param("period", period, period);
  pnh.param("rate", rate, rate);
  pnh.param("start_delay", start_delay, start_delay);
  chs_node::Motion motion;
  try {
    motion = chs_node::parseMotion(motion_name);
    if (!(period > 0.0) || !(rate > 0.0) || !(start_delay >= 0.0))
      throw std::invalid_argument("~period and ~rate must be > 0, ~start_delay >= 0");
  } catch (const std::exception& e) {
    ROS_FATAL("mannequin_animator: %s", e.what());
    return 1;
  }
  ros::Publisher pub = nh.advertise<sensor_msgs::JointState>("joint_states", 10);
  ROS_INFO("mannequin_animator: motion %s, period %g s, after %g s", motion_name.c_str(), period,
           start_delay);
  // Sim time when use_sim_time is set; the motion starts start_delay after the first tick, which
  // leaves a garment time to settle on the rest pose.
  ros::Time start;
  ros::Rate loop(rate);
  while (ros::ok()) {
    const ros::Time now = ros::Time::now();
    if (start.isZero() && !now.isZero()) start = now + ros::Duration(start_delay);
    sensor_msgs::JointState js;
    js.header.stamp = now;
    js.name = chs_node::mannequinJoints();
    js.position =
        chs_node::mannequinPose(motion, start.isZero() ? 0.0 : (now - start).toSec(), period);
    pub.publish(js);
    ros::spinOnce();
    loop.sleep();
  }
  return 0;
}
