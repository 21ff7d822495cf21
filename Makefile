# Seiche: the two commands of README.md, and a few more.
#   make demo    install what is missing, build, run the dam break (window, or headless)
#   make test    install what is missing, build, run every test
#   make build   build only (CONFIG=debug for a debug build)
#   make bench   the benchmark (docs/performance.md)
#   make plots   density and stage-time plots of the two paper scenes (docs/)
#   make install PREFIX=/usr/local   the library (.so and .a), headers, pkg-config files,
#                the runner and the scenes (docs/embedding.md); DESTDIR is honoured
CONFIG ?= release
JOBS ?= $(shell nproc)
SEICHE = build/bin/seiche

PREFIX ?= /usr/local

.PHONY: all setup build demo test bench plots clean install

all: build

setup:
	@tools/setup.sh

# premake lists source files explicitly and embeds the shaders (build/gen/): regenerate
# when a source directory or a shader changes.
build/Makefile: premake5.lua $(wildcard shaders/*/*) engine engine/core engine/gl engine/render engine/script engine/app fluid fluid/bullet demos/seiche demos/bench demos/embed demos/render_bench tests
	premake4 --file=premake5.lua gmake
	@# ar only adds members: a renamed or removed source would leave its old object in a
	@# library. The file list changed, so the libraries are made afresh.
	@rm -f build/bin/*.a build/lib/*.so
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

install: build
	tools/install.sh "$(PREFIX)"

clean:
	rm -rf build
