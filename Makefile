# The front door. `make test` sets up, builds and runs the tests; `make fig4` (fig3 ... fig9,
# table-vl) runs an experiment spec and draws its figure. Without a GPU the figure targets run on the
# host backend at a reduced scale, and say so.
BUILD ?= build
JOBS ?= 2
CMAKE_ARGS ?=
SPHBENCH := $(BUILD)/harness/sphbench
# The float64 build (-DSPH_DOUBLE=ON) that runs the runs asking for precision = "float64".
BUILD_F64 ?= build-f64
PYTHON ?= python3

.PHONY: accuracy build-float64 all deps configure build test figures fig3 fig4 fig5 fig6 fig7 fig8 fig9 multi-gpu cll-vs-vl table-vl perf-check clean

all: build

deps:
	@PYTHON=$(PYTHON) tools/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE="$$(command -v $(PYTHON))" $(CMAKE_ARGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

test: build
	@cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

# Figures 3 and 4 have a spec each; Figures 5 to 9 share the multi-gpu experiment (runs that
# are up to date are not run again, so `make fig5 fig6` runs it once).
fig3 fig4: fig%: build
	$(SPHBENCH) run experiments/fig$*.toml
	$(PYTHON) plots/fig$*.py

multi-gpu cll-vs-vl: build
	$(SPHBENCH) run experiments/$@.toml

fig5 fig6 fig7 fig8 fig9: fig%: multi-gpu
	$(PYTHON) plots/fig$*.py

table-vl: cll-vs-vl
	$(PYTHON) plots/table_vl.py

figures: fig3 fig4 fig5 fig6 fig7 fig8 fig9 table-vl

# Precision is fixed at compile time: a second build, sphbench only, for the float64 runs.
build-float64: deps
	@cmake -S . -B $(BUILD_F64) -DCMAKE_BUILD_TYPE=Release -DSPH_DOUBLE=ON -DSPH_BUILD_TESTS=OFF $(CMAKE_ARGS) >/dev/null
	@cmake --build $(BUILD_F64) -j$(JOBS) --target sphbench

# Issue 6: validation error against run time; float64 runs are handed to the float64 build.
accuracy: build build-float64
	$(SPHBENCH) run experiments/accuracy.toml --float64-binary $(BUILD_F64)/harness/sphbench
	$(PYTHON) plots/accuracy.py

perf-check: build
	$(SPHBENCH) run experiments/perf-smoke.toml --backend host --out results/perf-check --force
	$(SPHBENCH) compare results/reference/host/perf-smoke results/perf-check/perf-smoke --metrics counters

clean:
	rm -rf $(BUILD) $(BUILD_F64)
