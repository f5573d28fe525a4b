# The front door. `make test` sets up, builds and runs the tests; `make fig4` (fig3 ... fig10)
# runs an experiment spec and draws its figure. Without a GPU the figure targets run on the
# host backend at a reduced scale, and say so.
BUILD ?= build
JOBS ?= 2
CMAKE_ARGS ?=
SPHBENCH := $(BUILD)/harness/sphbench
PYTHON ?= python3

.PHONY: all deps configure build test figures fig4 perf-check clean

all: build

deps:
	@tools/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_ARGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

test: build
	@cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

fig%: build
	@test -f experiments/fig$*.toml || { echo "make: no experiment spec experiments/fig$*.toml"; exit 2; }
	$(SPHBENCH) run experiments/fig$*.toml
	$(PYTHON) plots/fig$*.py

figures: build
	@for spec in experiments/fig*.toml; do n=$$(basename $$spec .toml); $(MAKE) --no-print-directory $$n || exit $$?; done

perf-check: build
	$(SPHBENCH) run experiments/perf-smoke.toml --backend host --out results/perf-check --force
	$(SPHBENCH) compare results/reference/host/perf-smoke results/perf-check/perf-smoke

clean:
	rm -rf $(BUILD)
