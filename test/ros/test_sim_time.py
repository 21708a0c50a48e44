#!/usr/bin/python3
"""rostest (test/ros/sim_time.test): with use_sim_time the node's simulation follows /clock, not
the wall clock: 1 s of /clock gives about 1 s of simulation, and nothing moves while /clock
stands still."""
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Clock
from cloth_hair_sim.msg import SimStatus
from latest_message import LatestMessage
from small_cloth import load_small_cloth


class SimTime(unittest.TestCase):
    def setUp(self):
        self.clock = rospy.Publisher('/clock', Clock, queue_size=10)
        self.now = 0.0
        self.status = LatestMessage('/sim/status', SimStatus)

    def tick(self, seconds, step=0.01):
        """Advances /clock by `seconds` in `step` increments, one every 10 ms of wall time."""
        for _ in range(int(round(seconds / step))):
            self.now += step
            self.clock.publish(Clock(clock=rospy.Time.from_sec(self.now)))
            time.sleep(0.01)

    def sim_time(self):
        status = self.status.get()
        return None if status is None else status.sim_time

    def test_simulation_follows_clock(self):
        # The node waits for /clock before its services and timers run.
        deadline = time.time() + 20.0
        loaded = False
        while time.time() < deadline and not loaded:
            self.tick(0.01)
            try:
                rospy.wait_for_service('/sim/load_garment', timeout=0.05)
                loaded = True
            except rospy.ROSException:
                pass
        self.assertTrue(loaded, 'no ~load_garment service')
        self.assertTrue(load_small_cloth())
        # Until the first status with the garment arrives (subscriptions take a moment).
        for _ in range(200):
            status = self.status.get()
            if status is not None and status.garments == 1:
                break
            self.tick(0.01)
        self.tick(0.1)
        start = self.sim_time()
        self.assertIsNotNone(start, 'no ~status with the garment')
        self.tick(1.0)
        # A status sent at the last tick may still be on its way (a loaded machine): let it
        # arrive. With /clock standing no timer fires, so nothing newer can follow.
        time.sleep(0.3)
        after_tick = self.sim_time()
        time.sleep(1.0)  # wall time passes, /clock stands still
        after_pause = self.sim_time()
        self.tick(0.2)
        after_more = self.sim_time()
        print('sim time: %.3f -> %.3f after 1.0 s of /clock, %.3f after a 1 s wall pause, %.3f '
              'after 0.2 s more /clock' % (start, after_tick, after_pause, after_more))
        self.assertGreater(after_tick - start, 0.85)
        self.assertLess(after_tick - start, 1.1)
        self.assertEqual(after_pause, after_tick)
        self.assertGreater(after_more - after_pause, 0.1)
        self.assertLess(after_more - after_pause, 0.3)


if __name__ == '__main__':
    rospy.init_node('test_sim_time')
    rostest.rosrun('cloth_hair_sim', 'sim_time', SimTime)
