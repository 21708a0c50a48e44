#!/usr/bin/python3
"""rostest (test/ros/implicit_node.test): the node steps a garment with backward Euler
(~mpm/integration: backward_euler) at substeps of ~dt, far beyond the explicit bound, and reports
its solves in ~status: the sheet hangs from its pins and comes to rest without rollbacks."""
import time
import unittest

import rospy
import rostest
from cloth_hair_sim.msg import SimStatus
from cloth_hair_sim.srv import LoadGarment, LoadGarmentRequest
from latest_message import LatestMessage


class ImplicitNode(unittest.TestCase):
    def setUp(self):
        self.status = LatestMessage('/sim/status', SimStatus)

    def test_backward_euler_hangs_a_sheet(self):
        rospy.wait_for_service('/sim/load_garment', timeout=30.0)
        load = rospy.ServiceProxy('/sim/load_garment', LoadGarment)
        # 10 x 10 cm cotton, 5 x 5 quads, stood up (rectangle y -> world z by a quarter turn
        # about x) and hung from its top row (vertices 30..35).
        req = LoadGarmentRequest(name='sheet', rectangle_size=[0.1, 0.1], rectangle_cells=[5, 5],
                                 material='cotton_eischen', pinned=list(range(30, 36)))
        req.pose.orientation.x = 0.5 ** 0.5
        req.pose.orientation.w = 0.5 ** 0.5
        res = load(req)
        self.assertTrue(res.success, res.message)
        deadline = time.time() + 60.0
        status = None
        while time.time() < deadline:
            status = self.status.get()
            if status is not None and status.garments == 1 and status.sim_time > 1.0:
                break
            time.sleep(0.1)
        self.assertIsNotNone(status)
        print('backward Euler node: sim time %.3f s in %d substeps, last substep %.4f s, '
              'unconverged solves %d, rollbacks %d, kinetic energy %.3e J'
              % (status.sim_time, status.steps, status.dt, status.unconverged_solves,
                 status.rollbacks, status.kinetic_energy))
        self.assertGreater(status.sim_time, 1.0)
        self.assertEqual(status.dynamics_backend, 'mpm')
        # Substeps of ~dt: far beyond cotton's explicit bound (~3e-4 s at 2 cm quads).
        self.assertGreater(status.dt, 0.003)
        self.assertEqual(status.rollbacks, 0)
        self.assertEqual(status.unconverged_solves, 0)
        # A hanging sheet settles: backward Euler damps its swing within the second.
        self.assertLess(status.kinetic_energy, 1e-6)


if __name__ == '__main__':
    rospy.init_node('test_implicit_node')
    rostest.rosrun('cloth_hair_sim', 'implicit_node', ImplicitNode)
