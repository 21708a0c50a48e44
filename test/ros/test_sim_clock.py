#!/usr/bin/python3
"""rostest (test/ros/sim_clock.test): with ~publish_clock the node is the clock. With nothing to
step /clock runs at the wall's pace; with a garment it advances by exactly what the node
simulates (here a tenth of real time), and ~status is stamped on it; paused, it stands, and
~step advances it by the steps taken."""
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Clock
from cloth_hair_sim.msg import SimStatus
from std_srvs.srv import SetBool
from cloth_hair_sim.srv import StepSim
from latest_message import LatestMessage
from small_cloth import load_small_cloth


class SimClock(unittest.TestCase):
    def setUp(self):
        self.clock = LatestMessage('/clock', Clock)
        self.status = LatestMessage('/sim/status', SimStatus)

    def clock_now(self):
        c = self.clock.get()
        return None if c is None else c.clock.to_sec()

    def test_clock_follows_the_simulation(self):
        deadline = time.time() + 20.0
        while time.time() < deadline and self.clock_now() is None:
            time.sleep(0.05)
        self.assertIsNotNone(self.clock_now(), 'no /clock from the node')
        # Empty world: the clock runs at the requested pace of the wall.
        c0, w0 = self.clock_now(), time.time()
        time.sleep(1.0)
        idle_pace = (self.clock_now() - c0) / (time.time() - w0)
        rospy.wait_for_service('/sim/load_garment', timeout=20.0)
        self.assertTrue(load_small_cloth())
        for _ in range(100):
            status = self.status.get()
            if status is not None and status.garments == 1 and status.steps > 0:
                break
            time.sleep(0.05)
        s0, c1, w1 = self.status.get(), self.clock_now(), time.time()
        time.sleep(2.0)
        s1, c2, w2 = self.status.get(), self.clock_now(), time.time()
        clock_pace = (c2 - c1) / (w2 - w1)
        simulated = s1.sim_time - s0.sim_time
        stamped = (s1.header.stamp - s0.header.stamp).to_sec()
        print('idle: /clock at %.2f of the wall; with the garment: /clock at %.3f of the wall, '
              '%.3f s simulated while status stamps moved %.3f s' %
              (idle_pace, clock_pace, simulated, stamped))
        self.assertGreater(idle_pace, 0.7)
        self.assertLess(idle_pace, 1.3)
        self.assertGreater(clock_pace, 0.005)  # it advances (the garment's stable step is < 1 ms)
        self.assertLess(clock_pace, 0.3)  # 100 updates of 1 ms per wall second at most
        self.assertAlmostEqual(stamped, simulated, delta=0.01)

        pause = rospy.ServiceProxy('/sim/pause', SetBool)
        self.assertTrue(pause(True).success)
        time.sleep(0.3)  # an update under way ends
        c3 = self.clock_now()
        time.sleep(1.0)
        c4 = self.clock_now()
        step = rospy.ServiceProxy('/sim/step', StepSim)
        before = step(1).sim_time
        time.sleep(0.3)
        c5 = self.clock_now()
        after = step(10).sim_time
        time.sleep(0.3)
        c6 = self.clock_now()
        print('paused: /clock moved %.4f s in 1 s of wall; ~step 10: simulated %.4f s, /clock %.4f s'
              % (c4 - c3, after - before, c6 - c5))
        self.assertEqual(c4, c3)
        self.assertGreater(after - before, 0.0)
        self.assertAlmostEqual(c6 - c5, after - before, delta=1e-6)


if __name__ == '__main__':
    rospy.init_node('test_sim_clock')
    rostest.rosrun('cloth_hair_sim', 'sim_clock', SimClock)
