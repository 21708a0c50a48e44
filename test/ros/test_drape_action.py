#!/usr/bin/python3
"""rostest (test/ros/drape_action.test): the ~drape action. A goal streams feedback with growing
iteration counts and ends with the drape applied; a goal that would run for hours is cancelled,
ends preempted within a moment with a cancelled result, and the simulation steps on throughout
(the particle backend on cotton runs at about a tenth of real time here: only its progress is
checked)."""
import threading
import time
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from cloth_hair_sim.msg import DrapeSolveAction, DrapeSolveGoal, FixedAxes, SimStatus
from cloth_hair_sim.srv import LoadGarment, LoadGarmentRequest, RemoveGarment
from latest_message import LatestMessage

N = 16  # quads along each side of the 20 x 20 cm cloth
TABLE_TOP = 0.5


class Feedback(object):
    """The feedback of one goal, kept for the test thread."""

    def __init__(self):
        self._lock = threading.Lock()
        self.messages = []

    def __call__(self, feedback):
        with self._lock:
            self.messages.append(feedback)

    def count(self):
        with self._lock:
            return len(self.messages)

    def copy(self):
        with self._lock:
            return list(self.messages)


class DrapeActionTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.status = LatestMessage('/sim/status', SimStatus)
        rospy.wait_for_service('/sim/load_garment', timeout=30.0)
        cls.client = actionlib.SimpleActionClient('/sim/drape', DrapeSolveAction)
        if not cls.client.wait_for_server(rospy.Duration(30.0)):
            raise RuntimeError('no ~drape action server')

    def setUp(self):
        # The tablecloth of sim_node.test: on the frictionless top, the centre held in x and y and
        # the middle of the +x edge in y.
        req = LoadGarmentRequest(name='cloth', rectangle_size=[0.2, 0.2],
                                 rectangle_cells=[N, N], material='cotton_eischen',
                                 frame_id='table')
        req.pose.orientation.w = 1.0
        req.fixed = [FixedAxes(vertex=(N // 2) * (N + 1) + N // 2, axes='xy'),
                     FixedAxes(vertex=(N // 2) * (N + 1) + N, axes='y')]
        res = rospy.ServiceProxy('/sim/load_garment', LoadGarment)(req)
        self.assertTrue(res.success, res.message)

    def tearDown(self):
        rospy.ServiceProxy('/sim/remove_garment', RemoveGarment)(name='cloth')

    def sim_time(self):
        deadline = time.time() + 5.0
        while time.time() < deadline:
            s = self.status.get()
            if s is not None and s.garments == 1:
                return s.sim_time
            time.sleep(0.05)
        self.fail('no ~status with the garment')

    def test_goal_streams_feedback_and_drapes(self):
        feedback = Feedback()
        goal = DrapeSolveGoal(garment='cloth', method='fem_shell', stabilization=10.0)
        self.client.send_goal(goal, feedback_cb=feedback)
        self.assertTrue(self.client.wait_for_result(rospy.Duration(90.0)), 'no result')
        result = self.client.get_result()
        messages = feedback.copy()
        print('fem_shell drape: %s, %d feedback messages, last: load step %d, load factor %.3f, '
              'iteration %d of %d, residual %.2e' % (
                  result.message, len(messages), messages[-1].load_step,
                  messages[-1].load_factor, messages[-1].iteration,
                  messages[-1].total_iterations, messages[-1].residual))
        self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED, result.message)
        self.assertTrue(result.success and result.converged and not result.cancelled)
        self.assertEqual(len(result.mesh.vertices), (N + 1) ** 2)
        self.assertGreater(min(v.z for v in result.mesh.vertices), TABLE_TOP - 0.2)
        self.assertLess(max(v.z for v in result.mesh.vertices[:N + 1]), TABLE_TOP - 0.02)
        self.assertGreaterEqual(len(messages), 3)
        totals = [m.total_iterations for m in messages]
        self.assertEqual(totals, sorted(totals), 'total_iterations went back')
        self.assertGreater(totals[-1], totals[0])
        # The FEM drape minimises the energy at the full load (load factor 1 throughout); a load
        # path (arc length) would raise it step by step. Either way it never goes back.
        factors = [m.load_factor for m in messages]
        self.assertEqual(factors, sorted(factors), 'load_factor went back')
        self.assertTrue(all(0.0 < f <= 1.0 for f in factors), factors)
        elapsed = [m.elapsed for m in messages]
        self.assertEqual(elapsed, sorted(elapsed))
        self.assertGreaterEqual(result.iterations, totals[-1])

    def cancel_long_goal(self, goal):
        feedback = Feedback()
        before = self.sim_time()
        self.client.send_goal(goal, feedback_cb=feedback)
        deadline = time.time() + 30.0
        while feedback.count() < 3 and time.time() < deadline:
            time.sleep(0.01)
        self.assertGreaterEqual(feedback.count(), 3, 'no feedback')
        during = self.sim_time()
        cancelled_at = time.time()
        self.client.cancel_goal()
        self.assertTrue(self.client.wait_for_result(rospy.Duration(10.0)), 'no result')
        latency = time.time() - cancelled_at
        result = self.client.get_result()
        after = self.sim_time()
        time.sleep(1.0)
        later = self.sim_time()
        print('%s cancelled: %s; result %.3f s after the cancel, after %d feedback messages '
              '(%d iterations); sim time %.2f -> %.2f during the solve, %.2f -> %.2f in 1 s '
              'after it' % (goal.method, result.message, latency, feedback.count(),
                            feedback.copy()[-1].total_iterations, before, during, after, later))
        self.assertEqual(self.client.get_state(), GoalStatus.PREEMPTED, result.message)
        self.assertTrue(result.cancelled)
        self.assertFalse(result.success)
        self.assertIn('cancelled', result.message)
        self.assertEqual(len(result.mesh.vertices), (N + 1) ** 2)  # the last good state
        self.assertLess(latency, 2.0)
        self.assertGreater(during, before, 'the simulation stood still during the solve')
        self.assertGreater(later, after, 'the simulation stopped after the cancel')

    def test_cancel_stops_a_particle_solve(self):
        # A displacement tolerance no relaxation reaches and two billion iterations: hours.
        self.cancel_long_goal(DrapeSolveGoal(garment='cloth', method='particle',
                                             tolerance=1e-300, max_iterations=2000000000))

    def test_cancel_stops_a_fem_shell_solve(self):
        # A residual tolerance below round-off: no load step converges, and it would retry for
        # its 20 cutbacks of 30 iterations each (tens of seconds).
        self.cancel_long_goal(DrapeSolveGoal(garment='cloth', method='fem_shell',
                                             stabilization=10.0, tolerance=1e-300))


if __name__ == '__main__':
    rospy.init_node('test_drape_action')
    rostest.rosrun('cloth_hair_sim', 'drape_action', DrapeActionTest)
