# Seiche: the two commands of README.md, and a few more.
#   make demo    install what is missing, build, run the dam break (window, or headless)
#   make test    install what is missing, build, run every test
#   make build   build only (CONFIG=debug for a debug build)
#   make bench   the benchmark (docs/performance.md)
#   make plots   density and stage-time plots of the two paper scenes (docs/)
#   make install PREFIX=/usr/local   the library (.so and .a), headers, pkg-config files,
#                the runner and the scenes (docs/embedding.md); DESTDIR is honoured
#   make sanitize  the whole suite built with AddressSanitizer and UBSan (build/sanitize/)
#   make fuzz      the libFuzzer harnesses of tests/fuzz/, FUZZ_SECONDS each (docs/testing.md)
CONFIG ?= release
JOBS ?= $(shell nproc)
SEICHE = build/bin/seiche

PREFIX ?= /usr/local

.PHONY: all setup build demo test bench plots clean install gpu-check sanitize sanitize-build

all: build

setup:
	@tools/setup.sh

# premake lists source files explicitly and embeds the shaders (build/gen/): regenerate
# when a source directory or a shader changes.
build/Makefile: premake5.lua $(wildcard shaders/*/*) engine engine/core engine/gl engine/render engine/script engine/app fluid fluid/bullet demos/seiche demos/bench demos/embed tests
	premake4 --file=premake5.lua gmake
	@# ar only adds members: a renamed or removed source would leave its old object in a
	@# library, and a renamed test would leave its old program for run.sh to run. The file
	@# list changed, so the libraries and test programs are made afresh.
	@rm -f build/bin/*.a build/lib/*.so build/bin/test_* build/sanitize/bin/*.a build/sanitize/lib/*.so \
	       build/sanitize/bin/test_*
	@touch build/Makefile

build: setup build/Makefile
	$(MAKE) --no-print-directory -C build config=$(CONFIG) -j$(JOBS)

demo: build
	@tools/demo.sh

test: build
	@tests/run.sh

# The suite under AddressSanitizer (leaks included) and UndefinedBehaviorSanitizer: the
# sanitize configuration of premake5.lua into build/sanitize/, run by tests/sanitize.sh
# (the sanitizer options and the leak suppressions for Mesa; docs/testing.md).
sanitize-build: setup build/Makefile
	$(MAKE) --no-print-directory -C build config=sanitize -j$(JOBS)

sanitize: sanitize-build
	@tests/sanitize.sh

bench: build
	build/bin/seiche-bench

plots: build
	tools/plots.sh

install: build
	tools/install.sh "$(PREFIX)"

# The suite, every scene and the benchmark on the GL at hand, one report in build/gpu-check/
# (docs/performance.md; options: make gpu-check GPU_CHECK_ARGS="--frames 30").
gpu-check: build
	tools/gpu_check.sh $(GPU_CHECK_ARGS)

clean:
	rm -rf build
