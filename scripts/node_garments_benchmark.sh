#!/usr/bin/env bash
# The issue's many-garments node row: COUNT cotton garments of 8 x 8 cells (16 x 16 cm, 2 cm
# cells), each hanging from two corners, 30 cm apart in a row of rows, loaded one by one into the
# node (config/default.yaml: real_time_factor 1, no colliders) with the given integration and
# substep. Prints how long each load_garment took (while the garments already loaded step), then,
# over SECONDS of wall time, the achieved real-time factor and the latency of ~list_garments
# called every 0.25 s, then how long ~pause and each remove_garment took.
# Usage (after make build): scripts/node_garments_benchmark.sh [count] [integration] [dt] [seconds]
#   e.g. scripts/node_garments_benchmark.sh 20 lagrangian_implicit 0.0166667 20
set -euo pipefail
COUNT=${1:-20}
INTEGRATION=${2:-symplectic_euler}
DT=${3:-0.001}
SECONDS_WALL=${4:-20}
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
source "$ROOT/scripts/bench_node.sh"
bench_params 11398 "$INTEGRATION" "$DT"
bench_node
/usr/bin/python3 - "$COUNT" "$SECONDS_WALL" <<'PY'
import statistics
import sys
import time

import rospy
from cloth_hair_sim.msg import SimStatus
from cloth_hair_sim.srv import ListGarments, LoadGarment, LoadGarmentRequest, RemoveGarment
from std_srvs.srv import SetBool

count, seconds = int(sys.argv[1]), float(sys.argv[2])
rospy.init_node('node_garments_benchmark', anonymous=True)
rospy.wait_for_service('/sim/load_garment', timeout=30)
load = rospy.ServiceProxy('/sim/load_garment', LoadGarment)
listing = rospy.ServiceProxy('/sim/list_garments', ListGarments)
n, size, apart, per_row = 8, 0.16, 0.3, 5
loads = []
for k in range(count):
    req = LoadGarmentRequest(name='garment_%d' % k, rectangle_size=[size, size],
                             rectangle_cells=[n, n], material='cotton_eischen')
    req.pose.position.x = apart * (k % per_row)
    req.pose.position.y = apart * (k // per_row)
    req.pose.position.z = 1.0
    req.pose.orientation.w = 1.0
    req.pinned = [n * (n + 1), (n + 1) * (n + 1) - 1]  # the two corners of one edge
    t = time.time()
    res = load(req)
    loads.append(time.time() - t)
    if not res.success:
        sys.exit('load of garment %d failed: %s' % (k, res.message))
print('node garments: %d loads, each %.3f s median, %.3f s at most (the last %.3f s)' % (
    count, statistics.median(loads), max(loads), loads[-1]))
s0 = rospy.wait_for_message('/sim/status', SimStatus, timeout=30)
w0 = time.time()
latency = []
while time.time() - w0 < seconds:
    t = time.time()
    listed = listing()
    latency.append(time.time() - t)
    time.sleep(0.25)
s1 = rospy.wait_for_message('/sim/status', SimStatus, timeout=30)
wall = time.time() - w0
print('node garments: %d listed; %.3f s simulated in %.1f s of wall: real-time factor %.4f; '
      'substep %.2e s, rollbacks %d, solves short of the tolerance %d' % (
          len(listed.names), s1.sim_time - s0.sim_time, wall, (s1.sim_time - s0.sim_time) / wall,
          s1.dt, s1.rollbacks, s1.unconverged_solves))
print('node garments: ~list_garments latency median %.3f s, max %.3f s over %d calls' % (
    statistics.median(latency), max(latency), len(latency)))
# ~pause does not wait for the update either.
pause = rospy.ServiceProxy('/sim/pause', SetBool)
pauses = []
for k in range(10):
    for state in (True, False):
        t = time.time()
        pause(state)
        pauses.append(time.time() - t)
        time.sleep(0.1)
print('node garments: %d pause calls, each %.3f s median, %.3f s at most' % (
    len(pauses), statistics.median(pauses), max(pauses)))
# remove_garment, when an update is in progress, is queued for the next substep.
remove = rospy.ServiceProxy('/sim/remove_garment', RemoveGarment)
removals = []
for k in range(count):
    t = time.time()
    if not remove(name='garment_%d' % k).success:
        sys.exit('removal of garment %d failed' % k)
    removals.append(time.time() - t)
    time.sleep(0.1)
print('node garments: %d removals, each %.3f s median, %.3f s at most (the first %.3f s)' % (
    count, statistics.median(removals), max(removals), removals[0]))
PY
