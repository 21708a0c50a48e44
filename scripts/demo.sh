#!/usr/bin/env bash
# Runs launch/demo.launch for DURATION seconds under a virtual X server (Xvfb): the mannequin
# moves, a garment drapes over it (HAIR=0, the default: GARMENT, sheet by default) or hair grows
# on the back of its head (HAIR=1: HAIR_GUIDES guide strands, no garment unless GARMENT names
# one), rosbag records markers, tf, joint states and status, and rviz screenshots are saved as
# PNG. Every node runs on the simulator's clock, so the motion keeps pace with the simulation
# (the bag's times are simulated seconds). CONFIG: a node configuration instead of
# config/default.yaml. REALTIME=1: garments on the Lagrangian implicit step at 1/60 s substeps
# (launch argument realtime). Prints a summary: real-time factor, deepest penetration into the
# mannequin over the whole run.
# Usage: scripts/demo.sh [out_dir] [build_dir]
set -euo pipefail
OUT="$(realpath -m "${1:-demo_output}")"
BUILD="$(realpath "${2:-build}")"
DURATION="${DURATION:-20}"
MOTION="${MOTION:-arms_raise}"
HAIR="${HAIR:-0}"
HAIR_GUIDES="${HAIR_GUIDES:-80}"
CONFIG="${CONFIG:-}"  # a node configuration instead of config/default.yaml
if [ "${REALTIME:-0}" = 1 ]; then REALTIME_ARG=true; else REALTIME_ARG=false; fi
if [ "$HAIR" = 1 ]; then
  GARMENT="${GARMENT:-none}"
  HAIR_ARG=true
else
  GARMENT="${GARMENT:-sheet}"
  HAIR_ARG=false
fi
DISPLAY_NUM="${DISPLAY_NUM:-:99}"
export PATH="/usr/bin:$PATH" ROSCONSOLE_STDOUT_LINE_BUFFERED=1
set +u
# shellcheck disable=SC1091
source "$BUILD/devel/setup.bash"
set -u
mkdir -p "$OUT"
BAG="$OUT/demo.bag"
LOG="$OUT/demo_launch.log"
rm -f "$BAG" "$OUT"/demo_*.png

pids=()
cleanup() {  # only what this script started, newest first, politely (SIGINT)
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill -INT "${pids[$i]}" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap cleanup EXIT

Xvfb "$DISPLAY_NUM" -screen 0 1280x800x24 -nolisten tcp >"$OUT/xvfb.log" 2>&1 &
pids+=($!)
export DISPLAY="$DISPLAY_NUM"
sleep 1

echo "demo: ${DURATION} s of '$MOTION' with a $GARMENT, hair $HAIR_ARG ($HAIR_GUIDES guides) under" \
  "Xvfb $DISPLAY_NUM (log: $LOG)"
roslaunch cloth_hair_sim demo.launch rviz:=true record:=true bag:="$BAG" duration:="$DURATION" \
  garment:="$GARMENT" motion:="$MOTION" hair:="$HAIR_ARG" hair_guides:="$HAIR_GUIDES" \
  realtime:="$REALTIME_ARG" \
  ${CONFIG:+config:="$(realpath "$CONFIG")"} >"$LOG" 2>&1 &
launch_pid=$!
pids+=("$launch_pid")

# Screenshots while the arms rise and near the end. The simulator is the clock (demo.launch's
# sim_clock): the motion starts 1 s of simulated time in and cycles in 6 s, so a garment
# simulated at a tenth of real time has its arms up about 45 s of wall time in.
shot() {
  sleep "$1"
  import -window root "$OUT/demo_$2.png" 2>>"$OUT/xvfb.log" && echo "demo: screenshot $OUT/demo_$2.png"
}
shot $((DURATION * 3 / 5)) "mid" &
shots=($!)
shot $((DURATION - 3)) "end" &
shots+=($!)
wait "$launch_pid" || true
wait "${shots[@]}" || true
sleep 1  # rosbag renames demo.bag.active on its way out

if [ ! -s "$BAG" ]; then
  echo "demo: no bag was written; see $LOG" >&2
  exit 1
fi
python3 - "$BAG" <<'PY'
import sys
import rosbag
bag = rosbag.Bag(sys.argv[1])
info = bag.get_type_and_topic_info().topics
print('demo: bag %s (%.1f s)' % (sys.argv[1], bag.get_end_time() - bag.get_start_time()))
for name in sorted(info):
    print('  %-28s %6d messages  %s' % (name, info[name].message_count, info[name].msg_type))
status = [m for _, m, _ in bag.read_messages(topics=['/cloth_hair_sim/status'])]
running = [s for s in status if s.state == 'running']
if not running:
    sys.exit('demo: the simulation never ran (no running status); see the launch log')
last = running[-1]
rtf = sorted(s.real_time_factor for s in running)
print('demo: %d substeps, %.2f s simulated, %d vertices, %d colliders, %d rollbacks' %
      (last.steps, last.sim_time, last.vertices, last.colliders, last.rollbacks))
print('demo: real-time factor median %.2f (min %.2f), %.1f us per substep, deepest penetration '
      'into the colliders %.2f mm over the run (%.2f mm at the end)' %
      (rtf[len(rtf) // 2], rtf[0], 1e6 * last.wall_time_per_step,
       1e3 * max(s.deepest_penetration for s in running), 1e3 * last.deepest_penetration))
PY
echo "demo: files in $OUT (demo.bag, demo_mid.png, demo_end.png, demo_launch.log)"
