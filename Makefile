# The front door. `make test` sets up, builds and runs the tests; `make fig4` (fig3 ... fig9,
# table-vl) runs an experiment spec and draws its figure. Without a GPU the figure targets run on the
# host backend at a reduced scale, and say so. `make reference` (on a GPU machine) regenerates every
# committed GPU result, resumably; `make claims` writes every table of docs/results.md from them.
BUILD ?= build
JOBS ?= 2
CMAKE_ARGS ?=
SPHBENCH := $(BUILD)/harness/sphbench
# The float64 build (-DSPH_DOUBLE=ON) that runs the runs asking for precision = "float64".
BUILD_F64 ?= build-f64
PYTHON ?= python3

.PHONY: all deps configure build build-float64 test figures fig3 fig4 fig5 fig6 fig7 fig8 fig9 fig10 multi-gpu cll-vs-vl whole-run \
        transports table-vl perf-check perf-accept stability skip-bench accuracy spheric2 reference reference-figures claims clean

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

# Issue 25: whole events from rest (dam break 1.04M to 1 s, 4.04M to 0.3 s, armadillo 2980K
# over 1000 steps), seconds per simulated second and the lists' rebuilds, in results/whole-run/runs.csv.
whole-run: build
	$(SPHBENCH) run experiments/whole-run.toml

fig5 fig6 fig7 fig8 fig9: fig%: multi-gpu
	$(PYTHON) plots/fig$*.py

# Figure 10 (paper section 6): the final speedup on 1 to 4 GPUs with and without the
# communication optimisation of section 5.3.
fig10: build
	$(SPHBENCH) run experiments/fig10.toml
	$(PYTHON) plots/fig10.py

# Not a paper figure: the whole step per transport (staged, peer, nccl) on 1 and 2 GPUs.
transports: build
	$(SPHBENCH) run experiments/transports.toml
	$(PYTHON) plots/transports.py

table-vl: cll-vs-vl
	$(PYTHON) plots/table_vl.py

figures: fig3 fig4 fig5 fig6 fig7 fig8 fig9 fig10 table-vl

# Precision is fixed at compile time: a second build, sphbench only, for the float64 runs.
build-float64: deps
	@cmake -S . -B $(BUILD_F64) -DCMAKE_BUILD_TYPE=Release -DSPH_DOUBLE=ON -DSPH_BUILD_TESTS=OFF $(CMAKE_ARGS) >/dev/null
	@cmake --build $(BUILD_F64) -j$(JOBS) --target sphbench

# Validation error against run time; float64 runs are handed to the float64 build.
accuracy: build build-float64
	$(SPHBENCH) run experiments/accuracy.toml --float64-binary $(BUILD_F64)/harness/sphbench
	$(PYTHON) plots/accuracy.py

# Issue 27: SPHERIC Test 2 (experiments/spheric2.toml) to 2 s at three spacings, water heights and box
# pressures against the MARIN measurements and run time; DualSPHysics' runs of the same case are drawn
# beside ours where results/spheric2-dualsphysics/ holds them (`make reference` makes both on a GPU).
spheric2: build build-float64
	$(SPHBENCH) run experiments/spheric2.toml --float64-binary $(BUILD_F64)/harness/sphbench
	$(PYTHON) plots/spheric2.py

# What CI can hold without a GPU (docs/perf-check.md): the work counters of a small suite,
# exactly; instructions the host backend executes on fixed scenes (callgrind); and each CUDA
# kernel's registers, spills, shared memory and SASS, read from $(BUILD)'s CUDA objects
# (skipped, and said so, in a build without nvcc). `make perf-accept` rewrites the last two
# references after an intended change, so that it shows in the commit's diff.
PERF_REFERENCE := results/reference/host
perf-check: build
	$(SPHBENCH) run experiments/perf-smoke.toml --backend host --out results/perf-check --force
	$(SPHBENCH) compare results/reference/host/perf-smoke results/perf-check/perf-smoke --metrics counters
	$(PYTHON) tools/perf_check.py check --build $(BUILD) --reference $(PERF_REFERENCE) --out results/perf-check/host

perf-accept: build
	$(PYTHON) tools/perf_check.py accept --build $(BUILD) --reference $(PERF_REFERENCE)

# Stability studies (experiments/stability-*.toml, `sphbench stability`): CFL limits, still
# water, impacts, the armadillo collapse; on the host at a reduced scale, a few minutes.
# The host's reduced-scale scenes have 2,000 to 35,000 particles: one OpenMP thread is faster
# there than two (a step has a dozen parallel loops of microseconds each).
STABILITY_STUDIES := stability-cfl stability-still-water stability-impact stability-armadillo
STABILITY_THREADS ?= 1
stability: build
	@for s in $(STABILITY_STUDIES); do OMP_NUM_THREADS=$(STABILITY_THREADS) $(SPHBENCH) stability experiments/$$s.toml --quiet || exit $$?; done
	$(PYTHON) plots/stability.py

# What skipping unneeded work saves: diffusion compiled out, boundary not integrated, grid over
# the particles' bounding box (bench/skip_bench.cpp; CUDA when a GPU is present).
skip-bench: build
	$(BUILD)/bench/sph_skip_bench --benchmark_out=results/skip_bench.json --benchmark_out_format=json

# Every GPU reference result the GPUs present allow, into results/reference/<gpu>[-xN]/ (docs/gpu-machines.md):
# prints its plan and estimate, skips what is up to date,
# resumes where the last call stopped. REFERENCE_BUDGET_S=500 starts nothing that would not fit;
# PLAN=1 prints the plan only (also without a GPU); REFERENCE_ONLY="fig3 fig4" picks items.
# With a packed build (.carry/, tools/gpu-run.sh pack) it runs those binaries and builds nothing.
# (Nothing is built where there is no GPU: the script then says so in one sentence and fails.)
REFERENCE_PREREQS := $(if $(or $(filter-out 0,$(PLAN)),$(wildcard .carry/bin/sphbench),$(if $(shell nvidia-smi -L 2>/dev/null),,no-gpu)),,build build-float64)
REFERENCE_EXEC := $(if $(wildcard .carry/bin/sphbench),tools/gpu-run.sh exec)
reference: $(REFERENCE_PREREQS)
	@$(REFERENCE_EXEC) $(PYTHON) tools/reference.py $(if $(filter-out 0,$(PLAN)),--dry-run)

# The figures of the committed reference results (after they come back from a GPU machine).
reference-figures:
	$(PYTHON) tools/reference.py --figures-only

# Every table of measured figures in docs/results.md, from the committed results: the claims table
# (plots/claims.toml) and the others (plots/results_tables.toml); `make test` (ctests claims and
# results_tables) fails when a table differs from what this writes.
claims:
	$(PYTHON) plots/claims.py --write
	$(PYTHON) plots/results_tables.py --write

clean:
	rm -rf $(BUILD) $(BUILD_F64)
