# mixload: the two commands a user needs are `make demo` and `make test`.
BUILD ?= build
JOBS ?= $(shell nproc)
CTEST_ARGS ?=

.PHONY: deps build test demo slow clean

deps:
	bash scripts/deps.sh

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build $(BUILD) -j $(JOBS)

# CI tier: unit tests and tiny real OpenFOAM runs (slow studies are label `slow`, excluded here).
test: build
	cd $(BUILD) && ctest --output-on-failure -j 2 -LE slow $(CTEST_ARGS)

# The main job: a coarse quartz collapse at a = 2, printing its results and the plot's path.
demo: build
	$(BUILD)/app/mixload collapse --material quartz --aspect 2 --cells-per-length 15 --out runs/demo-collapse --rerun

# Slow studies (mesh independence, aspect-ratio sweeps): hours on 2 cores.
slow: build
	cd $(BUILD) && ctest --output-on-failure -L slow $(CTEST_ARGS)

clean:
	rm -rf $(BUILD)
