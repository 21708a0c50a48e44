#!/usr/bin/python3
"""rostest (test/ros/reconfigure.test): dynamic_reconfigure of cloth_hair_sim_node. The server
shows the values the node was launched with; gravity, the real-time factor, the marker options
and a garment's material change live with a visible effect; nonsense is refused and the previous
value kept."""
import math
import time
import unittest

import rospy
import rostest
from dynamic_reconfigure.client import Client
from cloth_hair_sim.msg import SimStatus
from cloth_hair_sim.srv import (ListGarments, LoadGarment, LoadGarmentRequest, RemoveGarment)
from visualization_msgs.msg import MarkerArray
from latest_message import LatestMessage


class Markers(object):
    """Counts ~markers messages and keeps the latest."""

    def __init__(self):
        self.count = 0
        self.latest = None
        rospy.Subscriber('/sim/markers', MarkerArray, self._store)

    def _store(self, msg):
        self.count += 1
        self.latest = msg

    def fresh(self):
        """The garment points and collider marker count of a message sent after this call."""
        seen = self.count
        end = time.time() + 5.0
        while self.count < seen + 2 and time.time() < end:
            time.sleep(0.01)
        points = [p for m in self.latest.markers if m.ns == 'garments' for p in m.points]
        colliders = len([m for m in self.latest.markers if m.ns == 'colliders'])
        return points, colliders


def mean(points, axis):
    return sum(getattr(p, axis) for p in points) / len(points)


class Reconfigure(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.status = LatestMessage('/sim/status', SimStatus)
        cls.markers = Markers()
        rospy.wait_for_service('/sim/load_garment', timeout=20.0)
        cls.client = Client('/sim', timeout=20.0)
        cls.load = rospy.ServiceProxy('/sim/load_garment', LoadGarment)
        cls.remove = rospy.ServiceProxy('/sim/remove_garment', RemoveGarment)
        cls.list = rospy.ServiceProxy('/sim/list_garments', ListGarments)

    def load_patch(self, name, pinned=()):
        req = LoadGarmentRequest(name=name, rectangle_size=[0.2, 0.2], rectangle_cells=[4, 4],
                                 material='cotton_eischen', pinned=list(pinned))
        req.pose.position.z = 1.0
        req.pose.orientation.w = 1.0
        res = self.load(req)
        self.assertTrue(res.success, res.message)
        end = time.time() + 10.0
        while time.time() < end:
            s = self.status.get()
            if s is not None and name in [n for n in self.list().names] and s.garments >= 1:
                return
            time.sleep(0.05)

    def statuses(self, seconds):
        out, last = [], None
        end = time.time() + seconds
        while time.time() < end:
            s = self.status.get()
            if s is not None and s is not last:
                out.append(s)
                last = s
            time.sleep(0.02)
        return out

    def test_1_shows_launch_values_and_changes_gravity_live(self):
        c = self.client.get_configuration(timeout=10.0)
        # Launched with gravity [0, 0, 0] and damping 0, not the .cfg defaults.
        self.assertEqual((c['gravity_x'], c['gravity_y'], c['gravity_z']), (0.0, 0.0, 0.0))
        self.assertEqual(c['damping'], 0.0)
        self.assertEqual(c['real_time_factor'], 1.0)
        self.load_patch('free')
        before, _ = self.markers.fresh()
        time.sleep(0.5)
        still, _ = self.markers.fresh()
        self.assertLess(abs(mean(still, 'x') - mean(before, 'x')), 1e-4, 'moved without gravity')
        self.assertEqual(self.client.update_configuration({'gravity_x': 2.0})['gravity_x'], 2.0)
        time.sleep(1.0)
        after, _ = self.markers.fresh()
        dx, dz = mean(after, 'x') - mean(still, 'x'), mean(after, 'z') - mean(still, 'z')
        print('gravity (2, 0, 0) m/s^2 for about 1 s: the patch moved %.3f m along x, %.5f m '
              'along z' % (dx, dz))
        self.assertGreater(dx, 0.2)
        self.assertLess(abs(dz), 1e-4)
        # NaN is refused: the previous gravity stays.
        c = self.client.update_configuration({'gravity_y': float('nan')})
        self.assertEqual((c['gravity_x'], c['gravity_y']), (2.0, 0.0))
        self.client.update_configuration({'gravity_x': 0.0, 'gravity_z': -9.81})
        self.assertTrue(self.remove(name='free').success)

    def test_2_real_time_factor(self):
        self.load_patch('timing')
        c = self.client.update_configuration({'real_time_factor': 0.5})
        self.assertEqual(c['real_time_factor'], 0.5)
        time.sleep(0.5)
        seen = self.statuses(2.0)
        rtf = sorted(s.real_time_factor for s in seen)[len(seen) // 2]
        simulated = seen[-1].sim_time - seen[0].sim_time
        wall = (seen[-1].header.stamp - seen[0].header.stamp).to_sec()
        print('real_time_factor 0.5: median achieved %.3f, %.3f s simulated in %.3f s' %
              (rtf, simulated, wall))
        self.assertGreater(rtf, 0.4)
        self.assertLess(rtf, 0.6)
        self.assertLess(abs(simulated / wall - 0.5), 0.1)
        for bad in (-1.0, float('nan')):
            self.assertEqual(self.client.update_configuration(
                {'real_time_factor': bad})['real_time_factor'], 0.5)
        self.client.update_configuration({'real_time_factor': 1.0})
        self.assertTrue(self.remove(name='timing').success)

    def test_3_material_of_a_named_garment(self):
        self.client.update_configuration({'damping': 3.0})
        # Vertices 20 and 24: the corners of the far edge; the rest hangs below them.
        self.load_patch('hung', pinned=[20, 24])
        c = self.client.update_configuration({'garment': 'nonexistent'})
        self.assertEqual(c['garment'], '')
        c = self.client.update_configuration({'garment': 'hung'})
        self.assertEqual(c['garment'], 'hung')
        young, density, poisson = c['young'], c['areal_density'], c['poisson']
        self.assertGreater(young, 0.0)
        self.assertGreater(density, 0.0)
        for change in ({'areal_density': -1.0}, {'young': float('nan')}, {'poisson': 0.7},
                       {'self_friction': 0.5}):  # the particle backend has no self contact
            c = self.client.update_configuration(change)
            self.assertEqual((c['young'], c['areal_density'], c['poisson'], c['self_friction']),
                             (young, density, poisson, 0.0), str(change))
        time.sleep(3.0)
        stiff, _ = self.markers.fresh()
        c = self.client.update_configuration({'young': young / 100.0})
        self.assertAlmostEqual(c['young'], young / 100.0)
        time.sleep(3.0)
        soft, _ = self.markers.fresh()
        low_stiff, low_soft = min(p.z for p in stiff), min(p.z for p in soft)
        print('hanging patch: lowest point %.4f m at E = %.3g Pa, %.4f m at E / 100' %
              (low_stiff, young, low_soft))
        self.assertLess(low_soft, low_stiff - 1e-3)
        self.assertTrue(all(math.isfinite(p.z) for p in soft))
        listing = self.list()
        self.assertIn('(reconfigured)', listing.materials[list(listing.names).index('hung')])
        self.assertTrue(self.remove(name='hung').success)

    def test_4_marker_options(self):
        _, colliders = self.markers.fresh()
        self.assertEqual(colliders, 1)
        self.client.update_configuration({'show_colliders': False, 'marker_rate': 5.0})
        time.sleep(0.5)
        _, colliders = self.markers.fresh()
        self.assertEqual(colliders, 0)
        start = self.markers.count
        time.sleep(2.0)
        rate = (self.markers.count - start) / 2.0
        print('marker_rate 5 Hz: %.1f messages per second' % rate)
        self.assertGreater(rate, 3.0)
        self.assertLess(rate, 7.0)
        c = self.client.update_configuration({'marker_rate': 0.0})
        self.assertEqual(c['marker_rate'], 5.0)


if __name__ == '__main__':
    rospy.init_node('test_reconfigure')
    rostest.rosrun('cloth_hair_sim', 'reconfigure', Reconfigure)
