#!/usr/bin/python3
"""rostest (test/ros/bag_record.test): a session recorded with rosbag is readable and holds the
garment markers, tf and status."""
import os
import time
import unittest

import rosbag
import rospy
import rostest
from cloth_hair_sim.srv import LoadGarment, LoadGarmentRequest

BAG = '/tmp/cloth_hair_sim_bag_test.bag'


class BagRecord(unittest.TestCase):
    def test_bag_holds_markers_tf_and_status(self):
        rospy.wait_for_service('/sim/load_garment', timeout=20.0)
        load = rospy.ServiceProxy('/sim/load_garment', LoadGarment)
        req = LoadGarmentRequest(name='cloth', rectangle_size=[0.2, 0.2], rectangle_cells=[4, 4],
                                 frame_id='table', material='cotton_eischen', pinned=[20, 24])
        req.pose.orientation.w = 1.0
        res = load(req)
        self.assertTrue(res.success, res.message)
        # The recorder closes the bag when its 6 s are up; the file then loses its .active suffix.
        deadline = time.time() + 40.0
        while time.time() < deadline and not os.path.exists(BAG):
            time.sleep(0.2)
        self.assertTrue(os.path.exists(BAG), 'rosbag record did not close ' + BAG)
        counts = {}
        triangles = {'garments': 0, 'garments_back': 0}
        with rosbag.Bag(BAG) as bag:
            for topic, msg, _ in bag.read_messages():
                counts[topic] = counts.get(topic, 0) + 1
                if topic == '/sim/markers':
                    for m in msg.markers:
                        if m.ns in triangles and m.type == m.TRIANGLE_LIST:
                            triangles[m.ns] = max(triangles[m.ns], len(m.points) // 3)
        print('bag %s: %s; largest garment marker %s triangles' % (BAG, counts, triangles))
        for topic in ('/sim/markers', '/sim/status', '/tf_static'):
            self.assertGreater(counts.get(topic, 0), 0, topic + ' missing from the bag')
        # The 4 x 4 quad sheet: at least its 32 front triangles (a limit-surface tessellation
        # has more), each with its back face.
        self.assertGreaterEqual(triangles['garments'], 32)
        self.assertEqual(triangles['garments_back'], triangles['garments'])


if __name__ == '__main__':
    if os.path.exists(BAG):
        os.remove(BAG)
    rospy.init_node('test_bag_record')
    rostest.rosrun('cloth_hair_sim', 'bag_record', BagRecord)
