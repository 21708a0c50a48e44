"""A 10 x 10 cm cotton cloth of 2 x 2 cells pinned at two corners, loaded through ~load_garment:
the smallest garment the node's rostests step."""
import rospy
from cloth_hair_sim.srv import LoadGarment, LoadGarmentRequest


def load_small_cloth(service='/sim/load_garment'):
    """Loads it as 'cloth'; returns whether the node accepted it."""
    load = rospy.ServiceProxy(service, LoadGarment)
    req = LoadGarmentRequest(name='cloth', rectangle_size=[0.1, 0.1], rectangle_cells=[2, 2],
                             material='cotton_eischen', pinned=[6, 8])
    req.pose.orientation.w = 1.0
    return load(req).success
