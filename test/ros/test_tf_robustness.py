#!/usr/bin/python3
"""rostest (test/ros/tf_robustness.test): the simulation holds and recovers when a collider's tf
frame (a) stops being published, (b) jumps 10 m in one update, with cloth resting on it or
grasped by it, (c) comes back after a gap at a slightly different pose. Checked each time: no
NaN, no rolled-back (diverged) steps, no cloth flung (kinetic energy), ~status naming the stale
collider while its frame is missing."""
import math
import threading
import time
import unittest

import rospy
import rostest
from cloth_hair_sim.msg import SimStatus
from cloth_hair_sim.srv import (GraspGarment, LoadGarment, LoadGarmentRequest, RemoveGarment)
from geometry_msgs.msg import TransformStamped
from std_srvs.srv import SetBool
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import MarkerArray
from latest_message import LatestMessage

TABLE_TOP = 0.3
# A resting 20 x 20 cm cotton patch (9.5 g) has no kinetic energy to speak of; one flung by a
# collider swept 10 m in 20 ms would have joules.
RESTING_ENERGY = 2e-3  # [J]


class Frames(object):
    """Publishes the test's frames on /tf at 100 Hz; a frame set to None is not published."""

    def __init__(self):
        self.lock = threading.Lock()
        self.poses = {}
        self.pub = rospy.Publisher('/tf', TFMessage, queue_size=10)
        self.timer = rospy.Timer(rospy.Duration(0.01), self._publish)

    def set(self, frame, xyz):
        with self.lock:
            self.poses[frame] = xyz

    def _publish(self, _event):
        msg = TFMessage()
        with self.lock:
            for frame, xyz in self.poses.items():
                if xyz is None:
                    continue
                t = TransformStamped()
                t.header.stamp = rospy.Time.now()
                t.header.frame_id = 'world'
                t.child_frame_id = frame
                t.transform.translation.x, t.transform.translation.y, \
                    t.transform.translation.z = xyz
                t.transform.rotation.w = 1.0
                msg.transforms.append(t)
        if msg.transforms:
            self.pub.publish(msg)


class Watch(object):
    """The latest garment points and status, and the extremes of the statuses over a while."""

    def __init__(self):
        self.status = LatestMessage('/sim/status', SimStatus)
        self.markers = LatestMessage('/sim/markers', MarkerArray)

    def points(self):
        m = self.markers.get()
        return [p for mk in m.markers if mk.ns == 'garments' for p in mk.points]

    def over(self, seconds):
        """Max kinetic energy, statuses and point sets seen during `seconds`."""
        statuses, clouds = [], []
        end = time.time() + seconds
        while time.time() < end:
            statuses.append(self.status.get())
            clouds.append(self.points())
            time.sleep(0.05)
        return max(s.kinetic_energy for s in statuses), statuses, clouds


def centre(points):
    n = float(len(points))
    return (sum(p.x for p in points) / n, sum(p.y for p in points) / n,
            sum(p.z for p in points) / n)


def finite(points):
    return all(math.isfinite(v) for p in points for v in (p.x, p.y, p.z))


class TfRobustness(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.frames = Frames()
        cls.watch = Watch()
        rospy.wait_for_service('/sim/load_garment', timeout=20.0)
        cls.load = rospy.ServiceProxy('/sim/load_garment', LoadGarment)
        cls.remove = rospy.ServiceProxy('/sim/remove_garment', RemoveGarment)
        cls.grasp = rospy.ServiceProxy('/sim/grasp', GraspGarment)
        cls.pause = rospy.ServiceProxy('/sim/pause', SetBool)

    def setUp(self):
        self.frames.set('table', (0.0, 0.0, TABLE_TOP))
        self.frames.set('hand', (0.0, 1.0, 0.8))
        end = time.time() + 10.0
        while time.time() < end:
            s = self.watch.status.get()
            if s is not None and s.transforms_ok and not s.stale_colliders:
                return
            time.sleep(0.05)
        self.fail('the frames never became current')

    def tearDown(self):
        self.remove(name='patch')

    def load_patch(self, xyz, grasp_radius=0.0):
        """Loads the patch (grasped by the hand right away if grasp_radius > 0) and lets it
        settle; returns the last status and points."""
        req = LoadGarmentRequest(name='patch', rectangle_size=[0.2, 0.2], rectangle_cells=[4, 4],
                                 material='cotton_eischen')
        req.pose.position.x, req.pose.position.y, req.pose.position.z = xyz
        req.pose.orientation.w = 1.0
        if grasp_radius > 0.0:  # paused: the patch must not fall away before the grasp closes
            self.assertTrue(self.pause(data=True).success)
        res = self.load(req)
        self.assertTrue(res.success, res.message)
        if grasp_radius > 0.0:
            res = self.grasp(name='hold', garment='patch', frame_id='hand', radius=grasp_radius)
            self.assertTrue(self.pause(data=False).success)
            self.assertTrue(res.success, res.message)
        time.sleep(3.0)  # falls or swings down and settles (damping 2 1/s)
        energy, statuses, clouds = self.watch.over(0.3)
        self.assertLess(energy, RESTING_ENERGY, 'the patch did not settle')
        return statuses[-1], clouds[-1]

    def check_calm(self, statuses, clouds, rollbacks, what):
        for c in clouds:
            self.assertTrue(finite(c), what + ': non-finite vertices')
        self.assertEqual(statuses[-1].rollbacks, rollbacks, what + ': diverged steps')
        self.assertEqual(statuses[-1].state, 'running', what)

    def test_a_frame_disappears(self):
        before, rest = self.load_patch((0.0, 0.0, TABLE_TOP + 0.01))
        self.frames.set('table', None)
        energy, statuses, clouds = self.watch.over(2.0)
        last = statuses[-1]
        print('table frame gone 2 s: stale %s, transforms_ok %s, patch centre z %.4f -> %.4f m, '
              'max kinetic energy %.2e J' % (list(last.stale_colliders), last.transforms_ok,
                                             centre(rest)[2], centre(clouds[-1])[2], energy))
        self.assertEqual(list(last.stale_colliders), ['table'])
        self.assertFalse(last.transforms_ok)
        self.check_calm(statuses, clouds, before.rollbacks, 'frame gone')
        # The table holds its last pose: the patch stays on it, at rest.
        self.assertLess(energy, RESTING_ENERGY)
        self.assertAlmostEqual(centre(clouds[-1])[2], centre(rest)[2], delta=0.005)

    def test_b_frame_jumps_under_resting_cloth(self):
        before, rest = self.load_patch((0.0, 0.0, TABLE_TOP + 0.01))
        self.frames.set('table', (10.0, 0.0, TABLE_TOP))
        energy, statuses, clouds = self.watch.over(2.0)
        end = centre(clouds[-1])
        print('table jumped 10 m: patch centre (%.3f, %.3f, %.3f) -> (%.3f, %.3f, %.3f) m, max '
              'kinetic energy %.3g J' % (centre(rest) + end + (energy,)))
        self.check_calm(statuses, clouds, before.rollbacks, 'table jump')
        # Not swept along at 500 m/s: the patch stays where it was and drops to the floor.
        self.assertLess(abs(end[0]), 0.2)
        self.assertLess(end[2], 0.05)
        self.assertLess(energy, 0.05)  # m g h = 0.028 J for the 0.3 m drop

    def test_b_frame_jumps_with_grasped_cloth(self):
        # Vertex 0 (a corner) at the hand; the grasp takes it and its two neighbours.
        before, hanging = self.load_patch((0.1, 1.1, 0.8), grasp_radius=0.06)
        self.frames.set('hand', (0.0, 11.0, 0.8))
        energy, statuses, clouds = self.watch.over(2.0)
        a, b = centre(hanging), centre(clouds[-1])
        print('hand jumped 10 m along y: hanging patch centre (%.3f, %.3f, %.3f) -> '
              '(%.3f, %.3f, %.3f) m, max kinetic energy %.3g J, grasps %s' %
              (a + b + (energy, list(statuses[-1].grasps))))
        self.check_calm(statuses, clouds, before.rollbacks, 'hand jump')
        # Carried with the hand, still held, not shaken.
        self.assertEqual(list(statuses[-1].grasps), ['hold'])
        self.assertAlmostEqual(b[1] - a[1], 10.0, delta=0.05)
        self.assertAlmostEqual(b[2], a[2], delta=0.05)
        # Typically 3.5e-5 J; once in four clean-clone runs 0.023 J (the grasp follows its frame
        # tf_delay in the past, where tf may still interpolate across the jump for an update or
        # two). Swept instead of placed, the cloth was thrown (thousands of rollbacks, above).
        self.assertLess(energy, 0.05)

    def test_c_frame_back_after_a_gap(self):
        before, rest = self.load_patch((0.0, 0.0, TABLE_TOP + 0.01))
        self.frames.set('table', None)
        energy, statuses, _ = self.watch.over(1.5)
        self.assertEqual(list(statuses[-1].stale_colliders), ['table'])
        # Back 3 cm higher: placed there (the cloth inside is pushed out), not swept up into it.
        self.frames.set('table', (0.0, 0.0, TABLE_TOP + 0.03))
        energy, statuses, clouds = self.watch.over(2.0)
        heights = [centre(c)[2] for c in clouds]
        print('table back 3 cm higher after 1.5 s: stale %s, patch centre z %.4f -> %.4f m '
              '(highest %.4f), max kinetic energy %.2e J' %
              (list(statuses[-1].stale_colliders), centre(rest)[2], heights[-1], max(heights),
               energy))
        self.assertEqual(list(statuses[-1].stale_colliders), [])
        self.assertTrue(statuses[-1].transforms_ok)
        self.check_calm(statuses, clouds, before.rollbacks, 'frame back')
        self.assertAlmostEqual(heights[-1], TABLE_TOP + 0.03, delta=0.01)
        self.assertLess(max(heights), TABLE_TOP + 0.045)  # no hop
        self.assertLess(energy, RESTING_ENERGY)


if __name__ == '__main__':
    rospy.init_node('test_tf_robustness')
    rostest.rosrun('cloth_hair_sim', 'tf_robustness', TfRobustness)
