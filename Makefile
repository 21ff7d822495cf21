# Seiche: the two commands of README.md, and a few more.
#   make demo    install what is missing, build, run the dam break (window, or headless)
#   make test    install what is missing, build, run every test
#   make build   build only (CONFIG=debug for a debug build)
#   make bench   the benchmark (docs/performance.md)
#   make plots   density and stage-time plots of the two paper scenes (docs/)
CONFIG ?= release
JOBS ?= $(shell nproc)
SEICHE = build/bin/seiche

.PHONY: all setup build demo test bench plots clean gpu-check

all: build

setup:
	@tools/setup.sh

# premake lists source files explicitly: regenerate when a source directory changes.
build/Makefile: premake5.lua engine engine/core engine/gl engine/render engine/script engine/app fluid fluid/bullet demos/seiche demos/bench demos/embed tests
	premake4 --file=premake5.lua gmake
	@touch build/Makefile

build: setup build/Makefile
	$(MAKE) --no-print-directory -C build config=$(CONFIG) -j$(JOBS)

demo: build
	@if [ -n "$${DISPLAY:-}$${WAYLAND_DISPLAY:-}" ]; then \
		$(SEICHE) scripts/scenes/dam_break.lua; \
	else \
		echo "demo: no display; running headless for 3 simulated seconds"; \
		$(SEICHE) --headless --frames 180 --screenshot build/dam_break.png scripts/scenes/dam_break.lua && \
		echo "demo: screenshot written to build/dam_break.png"; \
	fi

test: build
	@tests/run.sh

bench: build
	build/bin/seiche-bench

plots: build
	tools/plots.sh

# The suite, every scene and the benchmark on the GL at hand, one report in build/gpu-check/
# (docs/performance.md; options: make gpu-check GPU_CHECK_ARGS="--frames 30").
gpu-check: build
	tools/gpu_check.sh $(GPU_CHECK_ARGS)

clean:
	rm -rf build
