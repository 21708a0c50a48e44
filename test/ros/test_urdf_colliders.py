#!/usr/bin/python3
"""rostest (test/ros/urdf_colliders.test): the mannequin's URDF collision geometry appears as
colliders of cloth_hair_sim_node, and a collider follows its link when a joint moves."""
import math
import unittest

import rospy
import rostest
from cloth_hair_sim.msg import SimStatus
from sensor_msgs.msg import JointState
from visualization_msgs.msg import Marker, MarkerArray
from latest_message import LatestMessage

JOINTS = ['neck', 'shoulder_l', 'shoulder_r', 'elbow_l', 'elbow_r', 'hip_l', 'hip_r', 'knee_l',
          'knee_r']
# 17 links; the chest, neck, upper arms, forearms, thighs and shins are capsules written as
# cylinder + two spheres (fused into one collider each), the rest one sphere or box each.
EXPECTED_COLLIDERS = 17
# World position of the left elbow at rest: pelvis 0.96 + torso 0.08 + chest 0.18 + shoulder
# 0.24 - upper arm 0.29; the left forearm capsule's centre hangs 0.12 below it.
ELBOW_L = (0.0, 0.20, 0.96 + 0.08 + 0.18 + 0.24 - 0.29)
FOREARM_CENTRE = 0.12


class Latest(object):
    def __init__(self):
        self.status = LatestMessage('/sim/status', SimStatus)
        self.markers = LatestMessage('/sim/markers', MarkerArray)

    def wait(self, pred, timeout=15.0):
        end = rospy.get_time() + timeout
        while rospy.get_time() < end and not rospy.is_shutdown():
            status, markers = self.status.get(), self.markers.get()
            if status is not None and markers is not None and pred(status, markers):
                return status, markers
            rospy.sleep(0.05)
        return None, None


def collider_positions(markers):
    return {m.id: (m.pose.position.x, m.pose.position.y, m.pose.position.z)
            for m in markers.markers if m.ns == 'colliders' and m.action == Marker.ADD}


class UrdfCollidersTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_urdf_colliders')
        cls.latest = Latest()
        cls.elbow = 0.0
        cls.pub = rospy.Publisher('/joint_states', JointState, queue_size=10)
        cls.timer = rospy.Timer(rospy.Duration(0.02), cls.publish_joints)

    @classmethod
    def publish_joints(cls, _event):
        js = JointState()
        js.header.stamp = rospy.Time.now()
        js.name = JOINTS
        js.position = [cls.elbow if n == 'elbow_l' else 0.0 for n in JOINTS]
        cls.pub.publish(js)

    def settled(self, elbow):
        """Markers after the colliders have followed the elbow angle for a while."""
        type(self).elbow = elbow
        rospy.sleep(0.5)
        _, markers = self.latest.wait(
            lambda s, m: s.transforms_ok and len(collider_positions(m)) == EXPECTED_COLLIDERS)
        self.assertIsNotNone(markers, 'no markers with all %d colliders' % EXPECTED_COLLIDERS)
        return collider_positions(markers)

    def test_colliders_appear_and_follow_the_elbow(self):
        status, _ = self.latest.wait(lambda s, m: s.colliders == EXPECTED_COLLIDERS and
                                     s.transforms_ok and not s.stale_colliders)
        self.assertIsNotNone(status, 'status never reported %d colliders, all posed' %
                             EXPECTED_COLLIDERS)
        rest = self.settled(0.0)
        bent = self.settled(math.pi / 2)
        moved = [i for i in rest if math.dist(rest[i], bent[i]) > 1e-3]
        # The left forearm and the left hand move; nothing else does.
        self.assertEqual(len(moved), 2, 'moved colliders: %s' % moved)
        # The forearm capsule's centre: straight below the elbow, then straight ahead of it.
        below = (ELBOW_L[0], ELBOW_L[1], ELBOW_L[2] - FOREARM_CENTRE)
        ahead = (ELBOW_L[0] + FOREARM_CENTRE, ELBOW_L[1], ELBOW_L[2])
        forearm = [i for i in moved if math.dist(rest[i], below) < 1e-3]
        self.assertEqual(len(forearm), 1, 'no moved collider at the forearm centre %s' % (below,))
        self.assertLess(math.dist(bent[forearm[0]], ahead), 1e-3)


if __name__ == '__main__':
    rostest.rosrun('cloth_hair_sim', 'urdf_colliders', UrdfCollidersTest)
