#!/usr/bin/python3
"""rostest (test/ros/garment_mesh.test): each loaded garment publishes its state on
~garments/<name>/mesh at the marker rate, where it is; the topic goes away with the garment."""
import time
import unittest

import rosgraph
import rospy
import rostest
from std_srvs.srv import SetBool
from cloth_hair_sim.msg import GarmentMesh
from cloth_hair_sim.srv import LoadGarment, LoadGarmentRequest, RemoveGarment
from latest_message import LatestMessage

TOPIC = '/sim/garments/%s/mesh'


def publishers(topic):
    """Nodes the master lists as publishing topic."""
    pubs, _, _ = rosgraph.Master('/test_garment_mesh').getSystemState()
    return [nodes for name, nodes in pubs if name == topic]


class GarmentMeshTest(unittest.TestCase):
    def test_mesh_topic_follows_the_garment(self):
        rospy.wait_for_service('/sim/load_garment', timeout=30.0)
        rospy.ServiceProxy('/sim/pause', SetBool)(True)
        # A 0.3 x 0.2 m rectangle of 6 x 4 quads centred on (1, 2, 0.5), turned 90 degrees
        # about z: it spans x 1 +- 0.1, y 2 +- 0.15.
        req = LoadGarmentRequest(name='sheet', rectangle_size=[0.3, 0.2], rectangle_cells=[6, 4],
                                 material='cotton_eischen')
        req.pose.position.x, req.pose.position.y, req.pose.position.z = 1.0, 2.0, 0.5
        req.pose.orientation.z = req.pose.orientation.w = 0.5 ** 0.5
        self.assertTrue(rospy.ServiceProxy('/sim/load_garment', LoadGarment)(req).success)
        self.assertEqual(len(publishers(TOPIC % 'sheet')), 1)

        mesh = LatestMessage(TOPIC % 'sheet', GarmentMesh)
        deadline = time.time() + 10.0
        while mesh.get() is None and time.time() < deadline:
            time.sleep(0.05)
        m = mesh.get()
        self.assertIsNotNone(m, 'nothing on ' + TOPIC % 'sheet')
        self.assertEqual(m.name, 'sheet')
        self.assertEqual(m.header.frame_id, 'world')
        self.assertEqual(len(m.control_points), 7 * 5)
        self.assertEqual(len(m.velocities), 7 * 5)
        self.assertGreater(len(m.vertices), len(m.control_points))  # the tessellated surface
        self.assertGreater(len(m.triangles), 0)
        for t in m.triangles:
            self.assertTrue(all(0 <= i < len(m.vertices) for i in t.vertex_indices))
        for points in (m.control_points, m.vertices):
            xs, ys, zs = ([p.x for p in points], [p.y for p in points], [p.z for p in points])
            self.assertAlmostEqual(min(xs), 0.9, delta=1e-6)
            self.assertAlmostEqual(max(xs), 1.1, delta=1e-6)
            self.assertAlmostEqual(min(ys), 1.85, delta=1e-6)
            self.assertAlmostEqual(max(ys), 2.15, delta=1e-6)
            self.assertAlmostEqual(min(zs), 0.5, delta=1e-9)
            self.assertAlmostEqual(max(zs), 0.5, delta=1e-9)
        print('sheet: %d control points, %d surface vertices, %d triangles; x %.3f..%.3f, '
              'y %.3f..%.3f' % (len(m.control_points), len(m.vertices), len(m.triangles),
                                min(p.x for p in m.vertices), max(p.x for p in m.vertices),
                                min(p.y for p in m.vertices), max(p.y for p in m.vertices)))

        # Removed: the topic is unadvertised and nothing more arrives.
        self.assertTrue(rospy.ServiceProxy('/sim/remove_garment', RemoveGarment)('sheet').success)
        time.sleep(0.5)  # a message already on its way
        last = mesh.get()
        time.sleep(1.0)
        self.assertIs(mesh.get(), last, 'a mesh arrived after the removal')
        self.assertEqual(publishers(TOPIC % 'sheet'), [])


if __name__ == '__main__':
    rospy.init_node('test_garment_mesh')
    rostest.rosrun('cloth_hair_sim', 'garment_mesh', GarmentMeshTest)
