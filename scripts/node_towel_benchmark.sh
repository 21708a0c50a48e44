#!/usr/bin/env bash
# The issue's node row: a 50 x 50 cm cotton towel of 2 cm cells hanging from two corners, loaded
# into the node (config/default.yaml, no colliders, as fast as it can step) and stepped for
# SECONDS of wall time from its release; prints the achieved real-time factor.
# Usage (after make build): scripts/node_towel_benchmark.sh [integration] [dt] [seconds]
#   e.g. scripts/node_towel_benchmark.sh lagrangian_implicit 0.0166667 20
set -euo pipefail
INTEGRATION=${1:-symplectic_euler}
DT=${2:-0.001}
SECONDS_WALL=${3:-20}
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
source "$ROOT/scripts/bench_node.sh"
bench_params 11399 "$INTEGRATION" "$DT"
rosparam set /sim/real_time_factor 0.0
bench_node
/usr/bin/python3 - "$SECONDS_WALL" <<'PY'
import sys
import time

import rospy
from cloth_hair_sim.msg import SimStatus
from cloth_hair_sim.srv import LoadGarment, LoadGarmentRequest

rospy.init_node('node_towel_benchmark', anonymous=True)
rospy.wait_for_service('/sim/load_garment', timeout=30)
n = 25
req = LoadGarmentRequest(name='towel', rectangle_size=[0.5, 0.5], rectangle_cells=[n, n],
                         material='cotton_eischen')
req.pose.position.z = 1.0
req.pose.orientation.w = 1.0
req.pinned = [n * (n + 1), (n + 1) * (n + 1) - 1]  # the two corners of one edge
res = rospy.ServiceProxy('/sim/load_garment', LoadGarment)(req)
if not res.success:
    sys.exit('load failed: ' + res.message)
s0 = rospy.wait_for_message('/sim/status', SimStatus, timeout=30)
w0 = time.time()
time.sleep(float(sys.argv[1]))
s1 = rospy.wait_for_message('/sim/status', SimStatus, timeout=30)
wall = time.time() - w0
print('node towel: %.3f s simulated in %.1f s of wall: real-time factor %.4f; substep %.2e s, '
      'rollbacks %d, solves short of the tolerance %d' % (
          s1.sim_time - s0.sim_time, wall, (s1.sim_time - s0.sim_time) / wall, s1.dt,
          s1.rollbacks, s1.unconverged_solves))
PY
