#!/usr/bin/env bash
# How long ~reset holds the world: a 1.8 x 1.8 m cotton sheet of 90 x 90 cells (8281 vertices)
# hanging from two corners is loaded into the node (config/default.yaml with the given
# integration and substep, no colliders) and paused; then, three times, ~reset is called and 0.05 s
# later ~release (a service that takes the world's lock; here it finds no grasp of that name).
# Prints how long each reset took and how long the ~release call waited.
# Usage (after make build): scripts/node_reset_benchmark.sh [integration] [dt]
set -euo pipefail
INTEGRATION=${1:-lagrangian_implicit}
DT=${2:-0.0166667}
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
source "$ROOT/scripts/bench_node.sh"
bench_params 11399 "$INTEGRATION" "$DT"
bench_node
/usr/bin/python3 - <<'PY'
import threading
import time

import rospy
from cloth_hair_sim.srv import LoadGarment, LoadGarmentRequest, ReleaseGrasp
from std_srvs.srv import SetBool, Trigger

n = 90
rospy.init_node('node_reset_benchmark', anonymous=True)
rospy.wait_for_service('/sim/load_garment', timeout=30)
req = LoadGarmentRequest(name='sheet', rectangle_size=[1.8, 1.8], rectangle_cells=[n, n],
                         material='cotton_eischen')
req.pose.position.z = 1.0
req.pose.orientation.w = 1.0
req.pinned = [n * (n + 1), (n + 1) * (n + 1) - 1]
t = time.time()
res = rospy.ServiceProxy('/sim/load_garment', LoadGarment)(req)
print('node reset: load %.2f s: %s' % (time.time() - t, res.message))
rospy.ServiceProxy('/sim/pause', SetBool)(True)
time.sleep(1.0)
reset = rospy.ServiceProxy('/sim/reset', Trigger)
release = rospy.ServiceProxy('/sim/release', ReleaseGrasp)
for k in range(3):
    took = {}

    def call_reset():
        t = time.time()
        took['message'] = reset().message
        took['reset'] = time.time() - t

    caller = threading.Thread(target=call_reset)
    caller.start()
    time.sleep(0.05)
    t = time.time()
    release(name='none')
    took['release'] = time.time() - t
    caller.join()
    print('node reset: ~reset %.3f s; ~release called during it waited %.3f s (%s)' % (
        took['reset'], took['release'], took['message']))
    time.sleep(0.5)
PY
