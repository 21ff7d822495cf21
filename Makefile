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

.PHONY: all setup build demo test bench plots clean install gpu-check sanitize sanitize-build fuzz fuzz-build

all: build

setup:
	@tools/setup.sh

# premake lists source files explicitly and embeds the shaders (build/gen/): regenerate
# when a source directory or a shader changes.
# setup is order-only: premake4 comes from it, so under make -j it must finish first.
build/Makefile: premake5.lua $(wildcard shaders/*/*) engine engine/core engine/gl engine/render engine/script engine/app fluid fluid/bullet demos/seiche demos/bench demos/embed demos/embed_glfw demos/render_bench tests | setup
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

test: build fuzz-build
	@tests/run.sh

# The suite under AddressSanitizer (leaks included) and UndefinedBehaviorSanitizer: the
# sanitize configuration of premake5.lua into build/sanitize/, run by tests/sanitize.sh
# (the sanitizer options and the leak suppressions for Mesa; docs/testing.md).
sanitize-build: setup build/Makefile
	$(MAKE) --no-print-directory -C build config=sanitize -j$(JOBS)

sanitize: sanitize-build
	@tests/sanitize.sh

# libFuzzer harnesses (tests/fuzz/, docs/testing.md), built with clang and every sanitizer
# straight from the sources. make fuzz runs each for FUZZ_SECONDS (FUZZ_ARGS go to libFuzzer)
# with its corpus in build/fuzz/corpus/NAME; tests/run.sh runs each for a few seconds.
FUZZ_CC ?= clang-14
FUZZ_CXX ?= clang++-14
FUZZ_SECONDS ?= 60
FUZZ_ARGS ?=
FUZZ_CFLAGS = -std=c11 -D_POSIX_C_SOURCE=200809L -I. -g -O1 -fno-omit-frame-pointer \
	-fsanitize=fuzzer,address,undefined,float-cast-overflow -fno-sanitize-recover=all \
	-Wall -Wextra -pedantic -Wmissing-prototypes -Wstrict-prototypes -Wno-unused-function
FUZZ_NAMES = fuzz_params fuzz_glsl_preprocess fuzz_pbf_api fuzz_cli fuzz_lua_script fuzz_phys_api fuzz_cpl_api
FUZZ_BINS = $(addprefix build/fuzz/bin/,$(FUZZ_NAMES))
FLUID_SOURCES = $(filter-out fluid/pbf_cpu%.c,$(wildcard fluid/*.c)) build/gen/shaders_fluid.c
FLUID_HEADERS = $(wildcard fluid/*.h) shaders/fluid/pbf_shared.h tests/fuzz/fuzz_input.h tests/fuzz/fuzz_gl.h

build/fuzz/bin/fuzz_params: tests/fuzz/fuzz_params.c $(FLUID_SOURCES) $(FLUID_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -o $@ $(filter %.c,$^) -lepoxy -lm

build/fuzz/bin/fuzz_glsl_preprocess: tests/fuzz/fuzz_glsl_preprocess.c fluid/pbf_glsl.c $(FLUID_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -o $@ $(filter %.c,$^) -lepoxy

build/fuzz/bin/fuzz_pbf_api: tests/fuzz/fuzz_pbf_api.c $(FLUID_SOURCES) engine/gl/context.c engine/gl/gl_strict.c \
		engine/core/log.c $(FLUID_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -o $@ $(filter %.c,$^) -lepoxy -lglfw -lm

build/fuzz/bin/fuzz_cli: tests/fuzz/fuzz_cli.c engine/app/app_args.c engine/render/render_def.c engine/core/log.c \
		fluid/bullet/coupling_settings.c $(FLUID_SOURCES) \
		engine/app/app_args.h engine/app/app.h $(FLUID_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -o $@ $(filter %.c,$^) -lepoxy -lm

# The script harness needs most of the engine, Bullet's wrapper (C++) and Lua: compiled once
# into objects (build/fuzz/obj/, instrumented, header dependencies tracked), then linked.
FUZZ_OBJ_FLAGS = -g -O1 -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined,float-cast-overflow \
	-fno-sanitize-recover=all -I. -I/usr/include/lua5.4 -I/usr/include/bullet -I/usr/include/stb -MMD -MP
FUZZ_ENGINE_SOURCES = $(wildcard engine/core/*.c engine/gl/*.c engine/render/*.c engine/script/*.c) \
	build/gen/shaders_render.c fluid/bullet/coupling.c fluid/bullet/coupling_mesh.c fluid/bullet/coupling_settings.c \
	$(FLUID_SOURCES)
FUZZ_ENGINE_OBJECTS = $(patsubst %.c,build/fuzz/obj/%.o,$(FUZZ_ENGINE_SOURCES)) \
	$(patsubst %.cpp,build/fuzz/obj/%.o,$(wildcard fluid/bullet/phys*.cpp))
FUZZ_ENGINE_LIBS = -lepoxy -lEGL -lglfw -llua5.4 -lassimp -lBulletDynamics -lBulletCollision -lLinearMath -lcglm -lstb \
	-lstdc++ -lm -ldl -lpthread

build/fuzz/obj/%.o: %.c
	@mkdir -p $(@D)
	$(FUZZ_CC) -std=c11 -D_POSIX_C_SOURCE=200809L $(FUZZ_OBJ_FLAGS) -Wall -Wextra -Wno-unused-function -c -o $@ $<

build/fuzz/obj/%.o: %.cpp
	@mkdir -p $(@D)
	$(FUZZ_CXX) -std=c++17 $(FUZZ_OBJ_FLAGS) -fno-sanitize=vptr -Wall -Wextra -c -o $@ $<

-include $(FUZZ_ENGINE_OBJECTS:.o=.d)

build/fuzz/bin/fuzz_lua_script: tests/fuzz/fuzz_lua_script.c $(FUZZ_ENGINE_OBJECTS) $(FLUID_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize-link-c++-runtime -I/usr/include/lua5.4 -I/usr/include/bullet -o $@ $(filter %.c %.o,$^) \
		$(FUZZ_ENGINE_LIBS)

build/fuzz/bin/fuzz_phys_api: tests/fuzz/fuzz_phys_api.c $(patsubst %.cpp,build/fuzz/obj/%.o,$(wildcard fluid/bullet/phys*.cpp)) \
		fluid/bullet/phys.h tests/fuzz/fuzz_input.h
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize-link-c++-runtime -o $@ $(filter %.c %.o,$^) \
		-lBulletDynamics -lBulletCollision -lLinearMath -lstdc++ -lm

FUZZ_CPL_OBJECTS = $(patsubst %.c,build/fuzz/obj/%.o,$(FLUID_SOURCES) fluid/bullet/coupling.c fluid/bullet/coupling_mesh.c \
	fluid/bullet/coupling_settings.c engine/gl/context.c engine/gl/gl_strict.c engine/core/log.c) \
	$(patsubst %.cpp,build/fuzz/obj/%.o,$(wildcard fluid/bullet/phys*.cpp))
build/fuzz/bin/fuzz_cpl_api: tests/fuzz/fuzz_cpl_api.c $(FUZZ_CPL_OBJECTS) $(FLUID_HEADERS) fluid/bullet/coupling.h
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize-link-c++-runtime -I/usr/include/bullet -o $@ $(filter %.c %.o,$^) \
		-lepoxy -lEGL -lglfw -lBulletDynamics -lBulletCollision -lLinearMath -lstdc++ -lm -ldl -lpthread

# Written by premake with build/Makefile (and rewritten when a shader changes).
build/gen/shaders_fluid.c build/gen/shaders_render.c: | build/Makefile

# Without clang (FUZZ_CC) there is nothing to build: tests/run.sh then skips the harnesses.
fuzz-build: build/Makefile
	@if command -v $(FUZZ_CC) >/dev/null 2>&1; then $(MAKE) --no-print-directory $(FUZZ_BINS); \
	else echo "fuzz: $(FUZZ_CC) not found: the fuzz harnesses are not built"; fi

fuzz: fuzz-build
	@tests/fuzz/run.sh $(FUZZ_SECONDS) $(FUZZ_NAMES) -- $(FUZZ_ARGS)

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
