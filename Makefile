# Quick start on a bare Debian 12 (as root): `make demo` and `make test`.
BUILD ?= build
JOBS ?= 2
DEMO_OUT ?= demo_output
# Debian's catkin needs the system python (a pyenv python lacks catkin_pkg).
export PATH := /usr/bin:$(PATH)
# Paths under the checkout reach ccache relative to it, so clones and worktrees share its cache.
export CCACHE_BASEDIR := $(CURDIR)
CMAKE_FLAGS = -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DPython3_EXECUTABLE=/usr/bin/python3 -DCMAKE_CXX_COMPILER_LAUNCHER=ccache
BIN = $(BUILD)/devel/lib/cloth_hair_sim

.PHONY: deps build test demo format clean

deps:
	bash scripts/install-deps.sh

build: deps
	@# catkin caches the test environment at configure time with only the paths that exist then:
	@# without this directory a first build's rostests cannot import the generated messages.
	mkdir -p $(BUILD)/devel/lib/python3/dist-packages
	cmake -S . -B $(BUILD) $(CMAKE_FLAGS)
	cmake --build $(BUILD) -j$(JOBS)

# rostests need the package on ROS_PACKAGE_PATH: source the devel space first. ctest's exit
# status is the verdict (catkin_make run_tests would exit 0 on failure).
test: build
	cd $(BUILD) && ROSCONSOLE_STDOUT_LINE_BUFFERED=1 bash -c \
	  'source devel/setup.bash && ctest --output-on-failure -j$(JOBS)'

# The drape tool's tablecloth, then launch/demo.launch under Xvfb twice on the simulator's clock:
# the garment on the moving mannequin for DEMO_DURATION s ($(DEMO_OUT)/ros) and hair on its head
# for DEMO_HAIR_DURATION s ($(DEMO_OUT)/hair): a bag, rviz screenshots (PNG) and a summary
# (substeps, real-time factor, deepest penetration) in each.
DEMO_DURATION ?= 60
DEMO_HAIR_DURATION ?= 20
demo: build
	$(BIN)/drape scenes/tablecloth_fem.yaml --out $(DEMO_OUT)/tablecloth
	@echo "demo: draped mesh, report.json and pictures are in $(DEMO_OUT)/tablecloth"
	HAIR=0 DURATION=$(DEMO_DURATION) bash scripts/demo.sh $(DEMO_OUT)/ros $(BUILD)
	HAIR=1 DURATION=$(DEMO_HAIR_DURATION) bash scripts/demo.sh $(DEMO_OUT)/hair $(BUILD)

format:
	find include src test -name '*.h' -o -name '*.cpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD) $(DEMO_OUT)

# Benchmarks, run by hand (never by ctest): builds bench/*.cpp and writes the results to
# $(BENCH_OUT)/<name>.json and .txt (Google Benchmark) or .txt (the table-printing CLIs).
# BENCH_ARGS passes Google Benchmark flags, e.g. BENCH_ARGS=--benchmark_filter=Tablecloth.
# The CLIs take their defaults (short runs); see docs/BENCHMARKS.md for longer ones.
BENCH_OUT ?= $(BUILD)/bench_results
GBENCH = drape_benchmarks hybrid_shell_benchmarks
CLIBENCH = cloth_vs_bullet curtain_benchmark
.PHONY: bench
bench:
	cmake -S . -B $(BUILD) $(CMAKE_FLAGS)
	cmake --build $(BUILD) -j$(JOBS) --target $(GBENCH) $(CLIBENCH)
	mkdir -p $(BENCH_OUT)
	for b in $(GBENCH); do $(BIN)/$$b --benchmark_out=$(BENCH_OUT)/$$b.json \
	  --benchmark_out_format=json $(BENCH_ARGS) | tee $(BENCH_OUT)/$$b.txt; done
	for b in $(CLIBENCH); do $(BIN)/$$b | tee $(BENCH_OUT)/$$b.txt; done
