#!/usr/bin/python3
"""rostest (test/ros/diagnostics.test): the node's /diagnostics. A collider whose tf frame is
missing makes "Transforms" WARN and name it; once the frame is published every status is OK. A
garment that diverges and is stopped in place makes "Solver" ERROR and name it."""
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage
from cloth_hair_sim.srv import LoadGarment, LoadGarmentRequest

NAMES = ('Real-time factor', 'Solver', 'Transforms', 'Drape')


class Diagnostics(object):
    """The latest status of each name on /diagnostics."""

    def __init__(self):
        self._lock = threading.Lock()
        self._status = {}
        rospy.Subscriber('/diagnostics', DiagnosticArray, self._store)

    def _store(self, msg):
        with self._lock:
            for s in msg.status:
                self._status[s.name] = s

    def wait(self, predicate, timeout=20.0):
        """The statuses once predicate(statuses) holds, or the last ones at the timeout."""
        deadline = time.time() + timeout
        while True:
            with self._lock:
                status = dict(self._status)
            if predicate(status) or time.time() > deadline:
                return status
            time.sleep(0.05)


def node_status(status, node):
    """{name: status} of one node's four statuses, or None while one is missing."""
    out = {n: status.get('%s: %s' % (node, n)) for n in NAMES}
    return None if None in out.values() else out


def load(node, name, z, pinned):
    req = LoadGarmentRequest(name=name, rectangle_size=[0.1, 0.1], rectangle_cells=[4, 4],
                             material='cotton_eischen', pinned=pinned)
    req.pose.position.z = z
    req.pose.orientation.w = 1.0
    rospy.wait_for_service('/%s/load_garment' % node, timeout=30.0)
    return rospy.ServiceProxy('/%s/load_garment' % node, LoadGarment)(req)


def show(statuses):
    return '; '.join('%s [%d] %s' % (n, s.level, s.message) for n, s in sorted(statuses.items()))


class DiagnosticsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.diagnostics = Diagnostics()

    def test_stale_collider_warns_then_all_ok(self):
        # A cloth hanging from two corners, stepping at the requested real-time factor.
        self.assertTrue(load('sim', 'cloth', 0.5, [20, 24]).success)

        def stale(status):
            s = node_status(status, 'sim')
            return s is not None and s['Transforms'].level == DiagnosticStatus.WARN
        s = node_status(self.diagnostics.wait(stale), 'sim')
        self.assertIsNotNone(s, 'no /diagnostics from sim')
        print('frame missing: ' + show(s))
        self.assertEqual(s['Transforms'].level, DiagnosticStatus.WARN)
        self.assertIn("collider 'ghost'", s['Transforms'].message)
        self.assertIn('ghost_frame', s['Transforms'].message)
        self.assertEqual(s['Drape'].level, DiagnosticStatus.OK)

        # The frame appears: every status turns OK (the real-time factor once a full report
        # period was stepped).
        t = TransformStamped()
        t.header.stamp = rospy.Time.now()
        t.header.frame_id = 'world'
        t.child_frame_id = 'ghost_frame'
        t.transform.translation.x = 1.0
        t.transform.rotation.w = 1.0
        tf_static = rospy.Publisher('/tf_static', TFMessage, queue_size=1, latch=True)
        tf_static.publish(TFMessage(transforms=[t]))

        def all_ok(status):
            s = node_status(status, 'sim')
            return s is not None and all(x.level == DiagnosticStatus.OK for x in s.values())
        s = node_status(self.diagnostics.wait(all_ok), 'sim')
        print('frame published: ' + show(s))
        for name, status in s.items():
            self.assertEqual(status.level, DiagnosticStatus.OK, '%s: %s' % (name, status.message))
        self.assertIn('achieved', s['Real-time factor'].message)
        self.assertEqual(s['Solver'].values[0].key, 'rollbacks')

    def test_diverged_garment_is_an_error(self):
        # Free fall passes the node's max_speed of 5 cm/s after 5 ms: every substep from then
        # on is rolled back down to a sixteenth and the garment stopped in place.
        self.assertTrue(load('unstable', 'falling', 1.0, []).success)

        def error(status):
            s = node_status(status, 'unstable')
            return s is not None and s['Solver'].level == DiagnosticStatus.ERROR
        s = node_status(self.diagnostics.wait(error), 'unstable')
        self.assertIsNotNone(s, 'no /diagnostics from unstable')
        print('diverging: ' + show(s))
        self.assertEqual(s['Solver'].level, DiagnosticStatus.ERROR)
        self.assertIn("'falling'", s['Solver'].message)
        values = {v.key: v.value for v in s['Solver'].values}
        self.assertGreater(int(values['rollbacks']), 0)
        self.assertGreater(int(values['diverged stops of falling']), 0)


if __name__ == '__main__':
    rospy.init_node('test_diagnostics')
    rostest.rosrun('cloth_hair_sim', 'diagnostics', DiagnosticsTest)
