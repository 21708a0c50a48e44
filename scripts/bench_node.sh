# Sourced by the node benchmarks (scripts/node_*_benchmark.sh). bench_params PORT INTEGRATION DT:
# a ROS master of its own on PORT (beside any other) holding /sim's parameters, config/default.yaml
# with no colliders, the integration and the substep DT (the caller may set more); bench_node:
# the node as /sim. Both are stopped when the calling script exits. Needs ROOT (the repository).
export PATH=/usr/bin:$PATH  # ROS scripts need the system python
set +u  # the ROS setup scripts read unset variables
source "$ROOT/build/devel/setup.bash"
set -u
LOG=$(mktemp -d)
CORE=
NODE=
trap 'kill $NODE $CORE 2>/dev/null || true' EXIT

bench_params() {
  export ROS_MASTER_URI=http://127.0.0.1:$1
  roscore -p "$1" >"$LOG/roscore.log" 2>&1 &
  CORE=$!
  sleep 3
  rosparam load "$ROOT/config/default.yaml" /sim
  rosparam set /sim/mpm/integration "$2"
  rosparam set /sim/dt "$3"
  rosparam set /sim/colliders "[]"
}

bench_node() {
  "$ROOT/build/devel/lib/cloth_hair_sim/cloth_hair_sim_node" __name:=sim >"$LOG/node.log" 2>&1 &
  NODE=$!
}
