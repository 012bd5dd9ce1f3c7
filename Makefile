# mixload: the two commands a user needs are `make demo` and `make test`.
BUILD ?= build
JOBS ?= $(shell nproc)
CTEST_ARGS ?=

.PHONY: deps build test demo demo-collapse slow clean

deps:
	bash scripts/deps.sh

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build $(BUILD) -j $(JOBS)

# CI tier: unit tests and tiny real OpenFOAM runs (slow studies are label `slow`, excluded here).
test: build
	cd $(BUILD) && ctest --output-on-failure -j 2 -LE slow $(CTEST_ARGS)

# The main job: the mixer loading at the paper's reference point (Avicel, 39 rpm, 5 kg/h) from the
# shipped kriging model, and the paper's what-if: +50% bulk density with -10% or with -32% mu_s.
AVICEL = --mu-s 0.31 --mu-d 0.44 --i0 0.28 --d 240e-6 --rho 329.84
demo: build
	$(BUILD)/app/mixload predict $(AVICEL) --feed-kg-h 5 --rpm 39
	@echo "  full model here (1 cm, docs/paper-claims.md): 0.331 kg; the paper: 0.311 kg"
	$(BUILD)/app/mixload whatif $(AVICEL) --change rho=+50% --change mu_s=-10% --feed-kg-h 5 --rpm 39
	@echo "  full model for this change (1 cm, steady): +65.4% (0.548 kg); the paper: +25%"
	$(BUILD)/app/mixload whatif $(AVICEL) --change rho=+50% --change mu_s=-32% --feed-kg-h 5 --rpm 39
	@echo "  full model for this change (1 cm, steady): +76.6% (0.585 kg); the paper: -8%"

# The first full-CFD job: a coarse quartz collapse at a = 2, printing its results and the plot's path.
demo-collapse: build
	$(BUILD)/app/mixload collapse --material quartz --aspect 2 --cells-per-length 15 --out runs/demo-collapse --rerun

# Slow studies (mesh independence, aspect-ratio sweeps): hours on 2 cores.
slow: build
	cd $(BUILD) && ctest --output-on-failure -L slow $(CTEST_ARGS)

clean:
	rm -rf $(BUILD)
