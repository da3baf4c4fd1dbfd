# SPDX-License-Identifier: MIT
# libray -- plain Makefile.  Override any variable on the command line or
# in config.mak (e.g. CC=clang, CFLAGS=-O3, PREFIX=/usr, PNG=0).
#
# PNG=0 builds the library without libpng: src/image/png_none.c instead of
# src/image/png.c, whose PNG calls return RAY_ENOTSUP; build/nopng by default.
PNG        ?= 1
PREFIX     ?= /usr/local
LIBDIR     ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
MANDIR     ?= $(PREFIX)/share/man
PKGCONFIGDIR ?= $(LIBDIR)/pkgconfig
DOCDIR     ?= $(PREFIX)/share/doc/libray
CMAKEDIR   ?= $(LIBDIR)/cmake/libray
DESTDIR    ?=
CC         ?= cc
CXX        ?= c++
CFLAGS     ?= -O2 -g

# A quiet build: one short line a file ("CC src/scene/commit.c"), the
# commands themselves with V=1 (as Linux's and Git's Makefiles).
V ?= 0
ifeq ($(V),1)
Q :=
say := @:
else
Q := @
say := @printf '  %-5s %s\n'
endif
LDFLAGS    ?=
BUILD      ?= $(if $(filter 0,$(PNG)),build/nopng,build)
-include config.mak

ifeq ($(filter 0 1,$(PNG)),)
$(error PNG must be 1 (with libpng, the default) or 0 (without), not '$(PNG)')
endif

# The version is set in one place, include/ray.h's RAY_VERSION_MAJOR,
# _MINOR and _PATCH, and read from there here, by CMakeLists.txt and by
# what they write (libray.pc, the CMake package, the soname, the tarball);
# make version-test fails when any of them disagrees (mk/release.mk).
VERSION := $(shell awk '$$1 ~ /^.define$$/ && $$2 ~ /^RAY_VERSION_(MAJOR|MINOR|PATCH)$$/ \
               { v[$$2] = $$3 } END { print v["RAY_VERSION_MAJOR"] "." \
               v["RAY_VERSION_MINOR"] "." v["RAY_VERSION_PATCH"] }' include/ray.h)
SOMAJOR := $(firstword $(subst ., ,$(VERSION)))

# Always on, whatever CFLAGS says (they come after it on the command line,
# so they win): ISO C99 and no floating-point contraction.  gcc fuses a*b+c into an FMA in its GNU modes, which rounds
# the same edge differently in two neighbouring triangles and breaks
# watertightness (see ray-numerics(7); GCC manual, "Floating point
# implementation").
STD_CFLAGS = -std=c99 -D_POSIX_C_SOURCE=200809L -ffp-contract=off -fno-fast-math
WARN = -Wall -Wextra -Wpedantic -Wshadow -Wstrict-prototypes \
       -Wmissing-prototypes -Wwrite-strings -Wcast-qual -Wundef \
       -Wconversion -Wdouble-promotion -Wformat=2 -Wswitch-enum -Wvla
ALL_CFLAGS = $(WARN) -Iinclude $(CFLAGS) $(STD_CFLAGS)

PKG_CONFIG ?= pkg-config
# $(call memo,NAME,COMMAND), as NAME's value: COMMAND's output, run once a
# make, where NAME is first used, and kept (as MLINKS below).  The probes
# below ran again at every use: 166 pkg-config and 45 cc -print-multiarch
# processes a make check (issue 38).  On first use, not when the
# Makefile is read: after deps-build has installed what they ask about.
memo = $(eval $(1) := $$(shell $(2)))$($(1))
ifeq ($(PNG),1)
PNG_CFLAGS  = $(call memo,PNG_CFLAGS,$(PKG_CONFIG) --cflags libpng 2>/dev/null)
PNG_LIBS    = $(call memo,PNG_LIBS,$(PKG_CONFIG) --libs libpng 2>/dev/null || echo -lpng)
PNG_SRC_UNUSED = src/image/png_none.c
else
PNG_CFLAGS  =
PNG_LIBS    =
PNG_SRC_UNUSED = src/image/png.c
endif
# Check's header directory as a system one (-isystem), wherever it is
# installed: expanded in the tests, its ck_assert_*_tol macros compute in
# long double (-Wdouble-promotion) and use GNU's ", ## __VA_ARGS__"
# (clang's -Wgnu-zero-variadic-macro-arguments), warnings about Check's
# code, not ours.  In /usr/include it is a system header already.
CHECK_CFLAGS = $(patsubst -I%,-isystem %,$(call memo,CHECK_CFLAGS_PC,$(PKG_CONFIG) --cflags check 2>/dev/null))
CHECK_LIBS   = $(call memo,CHECK_LIBS,$(PKG_CONFIG) --libs check 2>/dev/null)
LIBS = $(PNG_LIBS) -lm -lpthread

SRCS = $(filter-out $(PNG_SRC_UNUSED),$(wildcard src/*/*.c))
OBJS = $(SRCS:src/%.c=$(BUILD)/obj/%.o)
# AMALGAMATION=1 makes both libraries of the one-file build instead
# (make amalgamation, mk/release.mk), its internal functions left
# external for the tests: .ci/run runs the whole suite so.
AMALGAMATION ?= 0
AMALG_DIR = $(BUILD)/amalgamation
LIB_OBJS = $(if $(filter 1,$(AMALGAMATION)),$(AMALG_DIR)/libray.o,$(OBJS))
PRIVATE_HEADERS = $(wildcard src/*/*.h)
STATIC = $(BUILD)/libray.a
SHARED = $(BUILD)/libray.so.$(VERSION)

TEST_SRCS = $(filter-out tests/check_main.c,$(wildcard tests/check_*.c))
TEST_BIN = $(BUILD)/tests/check_ray
# The fuzz targets (fuzz/fuzz_*.c), replayed over their committed inputs
# by make check ("fuzzing" below).
FUZZ_TARGETS = $(patsubst fuzz/%.c,%,$(wildcard fuzz/fuzz_*.c))
FUZZ_REPLAYS = $(FUZZ_TARGETS:%=$(BUILD)/fuzz-replay/%)
# examples/mpi_render.c needs MPI: built with mpicc, apart (make mpi-demo).
EXAMPLES = $(patsubst examples/%.c,$(BUILD)/examples/%,$(filter-out examples/mpi_render.c,$(wildcard examples/*.c)))
MANPAGES = $(wildcard man/man3/*.3) $(wildcard man/man7/*.7)
# Functions documented on another function's page, as page:alias: every
# name of a page's NAME section after its own (its .Nm lines, not those of
# later sections), so a new page needs no list here; docs-test checks
# that each is a function of ray.h shown in that page's SYNOPSIS.
# Worked out once a make, on first use (docs-test, install and uninstall
# each used to work it out again, and install-test's installs more).
MLINKS = $(eval MLINKS := $$(shell $$(MLINKS_CMD)))$(MLINKS)
# One awk over every page, not one (and a basename) a page: each make
# that needs the list (install-test's eight sub-makes, cmake-test's,
# version-test's) spent about a second of CPU on 94 processes for it.
MLINKS_CMD = awk 'FNR == 1 {p = FILENAME; sub(/.*\//, "", p); sub(/\.3$$/, "", p); name = 0} \
        /^\.Sh /{name = ($$2 == "NAME")} \
        name && /^\.Nm /{n=$$2; sub(/,$$/,"",n); \
        if (n != "" && n != p) print p ":" n}' man/man3/*.3

.PHONY: all lib check test demo bench-counts caustics-png sanitize tsan examples header-test symbols-test layers-test \
        man-lint docs-test license-test mutants-list-test install uninstall clean deps-build deps-check bench \
        deps-bench profile numerics links-test mpi-check mpi-render mpi-demo deps-mpi \
        fuzz fuzz-probe fuzz-build fuzz-run fuzz-replay check-suite check-faultsim \
        check-examples-run check-long check-long-suite bench-smoke bench-smoke-test \
        png-free-test install-test libray.pc cmake-config FORCE \
        amalgamation amalgamation-test amalgamation-test-long cmake-test abi-test abi-selftest layers-selftest abi-baseline exports-test \
        version-test dist distcheck print-srcs print-version deps-embed \
        snippets-test pages-test bench-docs-test windows-build windows-check \
        coverage coverage-run mutants check-o1

all: lib

lib: deps-build $(STATIC) $(SHARED)

# Only the showcase targets install missing Debian packages (apt-get, as
# root or with password-less sudo); plain make and make install only check
# and print the apt-get command to run.  deps-check waits for deps-build,
# so two apt-get never run at once.
SHOWCASE_GOALS = check check-long bench-smoke test demo mpi-demo bench numerics sanitize tsan examples \
    coverage mutants check-o1
DEPS_MODE = $(if $(filter $(SHOWCASE_GOALS),$(MAKECMDGOALS)),--install,--check)
DEPS_BUILD = pkg-config $(if $(filter 1,$(PNG)),libpng)
deps-build:
	@scripts/deps.sh $(DEPS_MODE) $(DEPS_BUILD)
deps-check: deps-build
	@scripts/deps.sh $(DEPS_MODE) $(DEPS_BUILD) check mandoc
# POV-Ray is optional: bench/whitted.c prints its own rows without it.
deps-bench: deps-build
	@scripts/deps.sh $(DEPS_MODE) $(DEPS_BUILD) gnuplot
	@scripts/deps.sh $(DEPS_MODE) povray 2>/dev/null || \
	    echo "libray: no povray: bench/whitted.c skips POV-Ray (apt-get install povray)" >&2

# src/query/intersect_avx2.c is the BVH queries again, built with -mavx2 where
# the compiler targets x86; intersect.c runs it only on CPUs with AVX2.
# src/scene/refit_avx2.c, the refit's leaf, likewise (triangles.c).
AVX2_SRCS = src/query/intersect_avx2.c src/scene/refit_avx2.c
AVX2_CFLAGS = $(if $(filter x86_64-% i386-% i486-% i586-% i686-% amd64-%,\
                $(call memo,CC_MACHINE,$(CC) -dumpmachine 2>/dev/null)),-mavx2)

# The package probes run before any compile (order-only), so a parallel
# make on a fresh machine does not compile against headers still being
# installed.
$(BUILD)/obj/%.o: src/%.c $(PRIVATE_HEADERS) include/ray.h | deps-build
	@mkdir -p $(@D)
	$(say) CC $<
	$(Q)$(CC) $(ALL_CFLAGS) -Isrc -fPIC -fvisibility=hidden -DRAY_BUILD \
	    $(if $(filter src/image/png.c,$<),$(PNG_CFLAGS)) \
	    $(if $(filter $(AVX2_SRCS),$<),$(AVX2_CFLAGS)) -c $< -o $@

# The PNG setting the objects were built with: rewritten only when it
# changes (as Linux's filechk), so that switching PNG in one BUILD
# re-links the libraries without png.o or png_none.o.
$(BUILD)/png.config: FORCE
	@mkdir -p $(@D)
	@echo "PNG=$(PNG)" | cmp -s - $@ || echo "PNG=$(PNG)" > $@

$(STATIC): $(LIB_OBJS) $(BUILD)/png.config
	$(say) AR $@
	$(Q)rm -f $@
	$(Q)$(AR) rcs $@ $(LIB_OBJS)

# Exports through a version script (src/libray.map): ray_* in node
# LIBRAY_$(SOMAJOR), everything else local, whatever -fvisibility says.
$(SHARED): $(LIB_OBJS) src/libray.map $(BUILD)/png.config
	$(say) LD $@
	$(Q)$(CC) $(CFLAGS) $(LDFLAGS) -shared -Wl,-soname,libray.so.$(SOMAJOR) \
	    -Wl,--version-script=src/libray.map -o $@ $(LIB_OBJS) $(LIBS)
	$(Q)ln -sf libray.so.$(VERSION) $(BUILD)/libray.so.$(SOMAJOR)
	$(Q)ln -sf libray.so.$(VERSION) $(BUILD)/libray.so

# ------------------------------------------------------------------ tests
# The suites are built with the library's warning list: a float constant
# (NAN, FLT_EPSILON) or a float pixel in a double expression is converted
# explicitly, as in src/.
# One object per suite, so that make -jN compiles them side by side (one
# cc command for all 44 files took a core for a minute and more).
TEST_OBJS = $(patsubst tests/%.c,$(BUILD)/tests/obj/%.o,tests/check_main.c $(TEST_SRCS))
$(BUILD)/tests/obj/%.o: tests/%.c $(wildcard tests/*.h) $(wildcard examples/*.h) bench/bench.h \
                        include/ray.h $(PRIVATE_HEADERS) | deps-check
	@mkdir -p $(@D)
	$(say) CC $<
	$(Q)$(CC) $(WARN) -Iinclude -Isrc -Iexamples -Ibench -Itests $(CFLAGS) $(STD_CFLAGS) \
	    $(CHECK_CFLAGS) $(PNG_CFLAGS) -DRAY_TEST_PNG=$(PNG) -c $< -o $@
$(TEST_BIN): $(TEST_OBJS) $(STATIC) | deps-check
	@mkdir -p $(@D)
	$(say) LD $@
	$(Q)$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $(TEST_OBJS) $(STATIC) $(CHECK_LIBS) $(LIBS)

# The allocation-failure sweep (tests/faultsim.c): the library's calls to
# these land in the program's __wrap_* functions, which fail them in turn.
FAULTSIM = $(BUILD)/tests/faultsim
comma = ,
FAULT_WRAPS = malloc calloc realloc free posix_memalign pthread_create \
    pthread_mutex_init \
    $(if $(filter 1,$(PNG)),png_image_write_to_memory)
$(FAULTSIM): tests/faultsim.c tests/testkit.h examples/common.h include/ray.h $(PRIVATE_HEADERS) $(STATIC)
	@mkdir -p $(@D)
	$(say) CC $@
	$(Q)$(CC) $(ALL_CFLAGS) -Iexamples -Isrc $(PNG_CFLAGS) -DRAY_TEST_PNG=$(PNG) $(LDFLAGS) -o $@ tests/faultsim.c \
	    $(STATIC) $(LIBS) $(patsubst %,-Wl$(comma)--wrap=%,$(FAULT_WRAPS))

# Each example an object first (EXAMPLE_OBJ), then linked: make check's
# amalgamation-test links the same objects with the one-file library
# (scripts/check-amalgamation.sh) instead of compiling seven examples
# again, with the same flags, into the same code (issue 38).
EXAMPLE_OBJ = $(BUILD)/examples/obj
$(EXAMPLE_OBJ)/%.o: examples/%.c $(wildcard examples/*.h) include/ray.h | deps-build
	@mkdir -p $(@D)
	$(say) CC $<
	$(Q)$(CC) $(ALL_CFLAGS) -c $< -o $@
$(BUILD)/examples/%: $(EXAMPLE_OBJ)/%.o $(STATIC)
	$(say) LD $@
	$(Q)$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $< $(STATIC) $(LIBS)
# Kept, not removed as intermediate files: amalgamation-test links them.
EXAMPLE_OBJS = $(EXAMPLES:$(BUILD)/examples/%=$(EXAMPLE_OBJ)/%.o)
.SECONDARY: $(EXAMPLE_OBJS)

examples: $(EXAMPLES)

# MPI (issue 20): mpi_render is built with MPICC (OpenMPI's wrapper, told
# to drive $(CC)) only where it exists; make check runs scripts/check-mpi.sh
# (byte identity against the plain examples, a failing rank) when mpicc and
# mpirun are there, and says it skipped them otherwise.  make mpi-demo
# installs OpenMPI (as make demo does its packages) and renders with 3
# ranks.  MPI_CHECK=0 skips the MPI tests (the ThreadSanitizer run: OpenMPI's
# own threads are not built for it).
MPICC ?= mpicc
# Without libpng (PNG=0) there is no picture to compare: skipped too.
MPI_CHECK ?= $(PNG)
MPI_RENDER = $(BUILD)/mpi/mpi_render
$(MPI_RENDER): examples/mpi_render.c $(wildcard examples/*.h) $(STATIC)
	@mkdir -p $(@D)
	OMPI_CC="$(CC)" $(MPICC) $(ALL_CFLAGS) $(LDFLAGS) -o $@ $< $(STATIC) $(LIBS)

# mpi-render builds mpi_render where the MPI tests run (MPI_CHECK=1,
# mpicc and mpirun there), for mpi-check and make check's
# bench-smoke-test (bench/mpi.sh), which wait for the program, not for
# each other.
MPI_HERE = [ "$(MPI_CHECK)" = 1 ] && command -v $(MPICC) >/dev/null 2>&1 && command -v mpirun >/dev/null 2>&1
mpi-render: lib
	@if $(MPI_HERE); then $(MAKE) --no-print-directory $(MPI_RENDER); fi
mpi-check: lib mpi-render $(BUILD)/examples/whitted $(BUILD)/examples/cornell $(BUILD)/examples/mesh $(BUILD)/examples/teapot
	@if [ "$(MPI_CHECK)" != 1 ]; then \
	    echo "check: MPI tests skipped (MPI_CHECK=$(MPI_CHECK))"; \
	elif $(MPI_HERE); then \
	    scripts/check-mpi.sh $(BUILD); \
	else \
	    echo "check: no mpicc/mpirun: MPI tests skipped (apt-get install libopenmpi-dev openmpi-bin, or make mpi-demo as root)"; \
	fi

deps-mpi: deps-build
	@scripts/deps.sh $(DEPS_MODE) mpi

mpi-demo: deps-mpi lib
	$(MAKE) --no-print-directory $(MPI_RENDER)
	OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
	    mpirun -np 3 --oversubscribe --bind-to none $(MPI_RENDER) whitted mpi_render.png

BENCHES = $(patsubst bench/%.c,$(BUILD)/bench/%,$(wildcard bench/*.c))
# make check builds the benchmarks so that none stops compiling unseen,
# but without the optional C++ comparators below (tinybvh, Bullet, CGAL
# and OpenVDB, where their headers are installed): those are other
# projects' code, compiled only to be timed beside ours, and cost make
# check 53 of its 535 CPU seconds where they are there (issue 38).  make
# bench and make bench-smoke build them (make bench-smoke-test, make
# check's smoke, does not, run alone or not); BENCH_COMPARE=1 or 0 chooses.
# The benchmarks that take them (and Embree: BENCH_EMBREE below) depend
# on BENCH_CONFIG, rewritten when either choice changes, so make bench
# after make check links them again.
BENCH_COMPARE ?= $(if $(filter check test bench-smoke-test,$(MAKECMDGOALS)),0,1)
BENCH_CONFIG = $(BUILD)/bench/compare.config
$(BENCH_CONFIG): FORCE
	@mkdir -p $(@D)
	@echo "BENCH_COMPARE=$(BENCH_COMPARE) BENCH_EMBREE=$(BENCH_EMBREE)" | cmp -s - $@ || \
	    echo "BENCH_COMPARE=$(BENCH_COMPARE) BENCH_EMBREE=$(BENCH_EMBREE)" > $@
$(BUILD)/bench/shapes $(BUILD)/bench/raycost $(BUILD)/bench/contains \
    $(BUILD)/bench/mesh $(BUILD)/bench/game $(BUILD)/bench/packets: $(BENCH_CONFIG)
# Embree is optional: used by the mesh, game and packets benchmarks when
# its header is there.  BENCH_EMBREE=0 builds them without it: make tsan
# does, where Embree's threads, not built for ThreadSanitizer, report
# races inside Embree that would fail make check's bench-smoke-test.
BENCH_EMBREE ?= 1
EMBREE_FLAGS = $(if $(filter 1,$(BENCH_EMBREE)),$(call memo,EMBREE_FLAGS,test -f /usr/include/embree3/rtcore.h && \
                 echo "-DHAVE_EMBREE"))
EMBREE_LIBS = $(if $(EMBREE_FLAGS),-lembree3)
EMBREE_BENCHES = bench/mesh.c bench/game.c bench/packets.c bench/raycost.c
# Bullet is optional too: bench/shapes.c compares the sweeps with its
# convexSweepTest and rayTest where Debian's libbullet-dev is installed.
# Bullet is C++: bench/bullet.cpp is built with $(CXX), only then.
BULLET_FLAGS = $(if $(filter 1,$(BENCH_COMPARE)),$(call memo,HAVE_BULLET,test -f /usr/include/bullet/btBulletCollisionCommon.h && \
                 echo "-DHAVE_BULLET"))
BULLET_OBJ = $(if $(BULLET_FLAGS),$(BUILD)/bench/bullet.o)
BULLET_LIBS = $(if $(BULLET_FLAGS),-lBulletCollision -lLinearMath -lstdc++)
$(BUILD)/bench/bullet.o: bench/bullet.cpp bench/shapes.h
	@mkdir -p $(@D)
	$(say) CXX $<
	$(Q)$(CXX) -O2 -g -Wall -Wextra -I/usr/include/bullet -Ibench -c $< -o $@
$(BUILD)/bench/shapes: $(BULLET_OBJ)
# tinybvh (../shared/ext/tiny_bvh.h, MIT) is the fastest float BVH set
# beside Embree by bench/raycost.c, when the header is there: C++, built
# with $(CXX) and AVX2 + FMA as its README asks, never part of the library.
TINYBVH_DIR ?= ../shared/ext
TINYBVH_FLAGS = $(if $(filter 1,$(BENCH_COMPARE)),$(call memo,HAVE_TINYBVH,test -f $(TINYBVH_DIR)/tiny_bvh.h && echo "-DHAVE_TINYBVH"))
TINYBVH_OBJ = $(if $(TINYBVH_FLAGS),$(BUILD)/bench/tinybvh.o)
TINYBVH_LIBS = $(if $(TINYBVH_FLAGS),-lstdc++)
$(BUILD)/bench/tinybvh.o: bench/tinybvh.cpp bench/tinybvh.h
	@mkdir -p $(@D)
	$(say) CXX $<
	$(Q)$(CXX) -O2 -mavx2 -mfma -w -I$(TINYBVH_DIR) -Ibench -c $< -o $@
$(BUILD)/bench/raycost: $(TINYBVH_OBJ)
# CGAL and OpenVDB are optional too (issue 39): bench/contains.c sets
# ray_contains beside CGAL's Side_of_triangle_mesh (Debian's libcgal-dev,
# header-only over GMP and MPFR) and ray_distance_grid beside OpenVDB's
# mesh-to-volume bakers (libopenvdb-dev, over TBB), each where its header
# is there.  bench/cgal_vdb.cpp is C++17, built with $(CXX) only then, and
# with -frounding-math, which CGAL's interval filters need under GCC
# (CGAL manual, "Using CGAL on GCC": its kernel checks it at start-up).
CGAL_FLAGS = $(call memo,CGAL_FLAGS,test -f /usr/include/CGAL/Side_of_triangle_mesh.h && \
               echo "-DHAVE_CGAL")
OPENVDB_FLAGS = $(call memo,OPENVDB_FLAGS,test -f /usr/include/openvdb/tools/MeshToVolume.h && \
                  echo "-DHAVE_OPENVDB")
CGAL_VDB_FLAGS = $(if $(filter 1,$(BENCH_COMPARE)),$(strip $(CGAL_FLAGS) $(OPENVDB_FLAGS)))
CGAL_VDB_OBJ = $(if $(CGAL_VDB_FLAGS),$(BUILD)/bench/cgal_vdb.o)
CGAL_VDB_LIBS = $(if $(CGAL_VDB_OBJ),$(if $(CGAL_FLAGS),-lmpfr -lgmp) \
                $(if $(OPENVDB_FLAGS),-lopenvdb -ltbb $(call memo,IMATH_LIBS,$(PKG_CONFIG) --libs Imath 2>/dev/null || echo -lImath)) -lstdc++)
$(BUILD)/bench/cgal_vdb.o: bench/cgal_vdb.cpp bench/cgal_vdb.h
	@mkdir -p $(@D)
	$(say) CXX $<
	$(Q)$(CXX) -std=c++17 -O2 -g -frounding-math -Wall -Wextra $(CGAL_VDB_FLAGS) -Ibench -c $< -o $@
$(BUILD)/bench/contains: $(CGAL_VDB_OBJ)
# Benchmarks mix float, double and long double on purpose (float variants,
# long double references), so -Wdouble-promotion, which guards the
# library's geometry code, is off for them.
$(BUILD)/bench/%: bench/%.c $(wildcard bench/*.h) $(wildcard examples/*.h) $(wildcard tests/*.h) $(STATIC)
	@mkdir -p $(@D)
	$(say) CC $<
	$(Q)$(CC) $(ALL_CFLAGS) -Wno-double-promotion -Iexamples -Itests -Isrc $(if $(filter $(EMBREE_BENCHES),$<),$(EMBREE_FLAGS)) \
	    $(if $(filter bench/shapes.c,$<),$(BULLET_FLAGS)) $(if $(filter bench/raycost.c,$<),$(TINYBVH_FLAGS)) \
	    $(if $(filter bench/contains.c,$<),$(CGAL_VDB_FLAGS)) $(PNG_CFLAGS) -DBENCH_PNG=$(PNG) \
	    $(LDFLAGS) -o $@ $< $(if $(filter bench/shapes.c,$<),$(BULLET_OBJ)) $(if $(filter bench/raycost.c,$<),$(TINYBVH_OBJ)) \
	    $(if $(filter bench/contains.c,$<),$(CGAL_VDB_OBJ)) $(STATIC) $(if $(filter $(EMBREE_BENCHES),$<),$(EMBREE_LIBS)) \
	    $(if $(filter bench/shapes.c,$<),$(BULLET_LIBS)) $(if $(filter bench/raycost.c,$<),$(TINYBVH_LIBS)) \
	    $(if $(filter bench/contains.c,$<),$(CGAL_VDB_LIBS)) $(LIBS)

# Benchmarks print figures (Markdown tables) and compare within one run;
# they assert nothing.  bench/run.sh writes bench/RESULTS.md, copies its
# tables into doc/BENCHMARKS.md and doc/NUMERICS.md (bench/run.sh --splice
# does only that, from the RESULTS.md there is; make check's
# bench-docs-test checks it was done) and draws bench/accuracy.png with gnuplot
# (installed here like the other targets' packages).  BENCH_QUICK=1 for a
# short run, written to bench/RESULTS-quick.md and accuracy-quick.png
# (untracked) so that it never replaces the documented figures.
bench: deps-bench lib $(BENCHES) bench-counts
	@if command -v $(MPICC) >/dev/null 2>&1; then $(MAKE) --no-print-directory $(MPI_RENDER); fi
	bench/run.sh $(BUILD)

# The queries' work per ray (issue 34): bench/raycost against the library
# compiled with -DRAY_BENCH_COUNTS, in a build of its own, which prints
# the work counters (src/query/query.h: RAY__WORK) instead of times;
# bench/run.sh runs it after the timed raycost.  Never the library proper.
bench-counts: deps-bench
	@$(MAKE) --no-print-directory BUILD=$(BUILD)/counts \
	    CFLAGS="$(CFLAGS) -DRAY_BENCH_COUNTS" $(BUILD)/counts/bench/raycost

# Where a query's time goes (issue 27): perf's samples of bench/filter's
# camera rays and cosine rays alone, and of its refits (filter --profile),
# one thread, by function.  Needs perf (Debian's linux-perf); prints, asserts nothing.
PROFILE_MESH ?= data/bunny-2.obj
profile: $(BUILD)/bench/filter
	@scripts/fetch-bunny.sh data >/dev/null
	@command -v perf >/dev/null || { echo "profile: no perf (apt-get install linux-perf)" >&2; exit 1; }
	@for kind in primary incoherent refit; do \
	    perf record -q -o $(BUILD)/perf.$$kind.data \
	        $(BUILD)/bench/filter --profile $(PROFILE_MESH) $$kind || exit 1; \
	    perf report -i $(BUILD)/perf.$$kind.data --stdio --sort symbol 2>/dev/null | \
	        grep '%' | head -12; \
	done

# The stability suite alone (doc/NUMERICS.md): the table of hard cases,
# naive against robust (bench/numerics.c), then the Check suite's numerics
# tests by themselves (CK_RUN_SUITE, Check's own variable).
numerics: deps-check lib $(BUILD)/bench/numerics $(TEST_BIN)
	$(BUILD)/bench/numerics
	CK_RUN_SUITE=numerics $(TEST_BIN)

# The header alone must compile as strict C99 and as C++.
header-test: include/ray.h tests/header_c99.c
	@mkdir -p $(BUILD)
	$(CC) -std=c99 -Wall -Wextra -Wpedantic -Werror -Iinclude -c \
	    tests/header_c99.c -o $(BUILD)/header_c99.o
	@if command -v $(CXX) >/dev/null 2>&1; then \
	    echo "$(CXX) -x c++ -Wall -Wextra -Werror -Iinclude -c tests/header_c99.c"; \
	    $(CXX) -x c++ -Wall -Wextra -Werror -Iinclude -c tests/header_c99.c \
	        -o $(BUILD)/header_cxx.o; \
	else echo "header-test: no C++ compiler ($(CXX)), C++ check skipped"; fi

# Only ray_* symbols may leave the shared library, each in version node
# LIBRAY_<major version of ray.h> (objdump -T prints the node before the
# name; src/libray.map names it, so a major version moved without the
# node fails here); ray.h's static inline helpers (ray_vec3_*, ray_rgb_*)
# none.
symbols-test: $(SHARED)
	@bad=$$(nm -D --defined-only $(SHARED) | awk '$$2 != "A" {print $$3}' | grep -v '^ray_' || true); \
	if [ -n "$$bad" ]; then echo "symbols-test: unexpected exports: $$bad"; exit 1; fi; \
	inline=$$(nm -D --defined-only $(SHARED) | awk '{print $$3}' | grep -E '^ray_(vec3|rgb)_' || true); \
	if [ -n "$$inline" ]; then echo "symbols-test: ray.h's static inline helpers exported: $$inline"; exit 1; fi; \
	unversioned=$$(objdump -T $(SHARED) | awk '$$NF ~ /^ray_/ && $$(NF-1) != "LIBRAY_$(SOMAJOR)" {print $$NF}'); \
	if [ -n "$$unversioned" ]; then echo "symbols-test: not in LIBRAY_$(SOMAJOR): $$unversioned"; exit 1; fi; \
	echo "symbols-test: exports: $$(nm -D --defined-only $(SHARED) | awk '$$2 != "A" {print $$3}' | tr '\n' ' ')"

# Every file says its licence (scripts/check-spdx.sh: which files, and
# why the PNGs and LICENSE itself are exempt).
license-test:
	@scripts/check-spdx.sh

# The mutants' list against the tree (a second): every snippet of
# tests/mutants.txt still occurs once in its file, so that code that moved
# on cannot leave a mutant behind that make mutants would refuse.
mutants-list-test:
	@MUTANTS_CHECK_ONLY=1 tests/mutants.sh

man-lint:
	@test -n "$(MANPAGES)" || { echo "man-lint: no man pages found"; exit 1; }
	@if command -v mandoc >/dev/null 2>&1; then \
	    echo "mandoc -Tlint -W warning man/..."; \
	    mandoc -Tlint -W warning $(MANPAGES); \
	else \
	    echo "groff -mdoc -ww -z man/... (mandoc not installed)"; \
	    for f in $(MANPAGES); do groff -mdoc -ww -z $$f || exit 1; done; \
	fi

# The man pages state what include/ray.h states: every RAY_API prototype,
# with the same return type and parameter types and names, in the
# SYNOPSIS and NAME of one page, installed as that page or as one of the
# MLINKS above; the types, constants and struct copies shown there too
# (scripts/check-docs.sh says all it checks).  MLINKS is passed in so that
# the list the install rule uses is the one checked.
docs-test:
	@MLINKS="$(MLINKS)" scripts/check-docs.sh
	@MLINKS="$(MLINKS)" scripts/test-check-docs.sh

# Every relative link of README.md and doc/*.md resolves, anchors too.
links-test:
	@scripts/check-links.sh

# The pages show what runs (issue 29): every program README.md and
# doc/*.md show (<!-- program -->) compiles with the library's warnings
# as errors, links and runs; every output they show (<!-- output -->) is
# what it prints (scripts/check-snippets.sh).
snippets-test: $(STATIC) $(EXAMPLES)
	@CC="$(CC)" CFLAGS="$(ALL_CFLAGS)" LDFLAGS="$(LDFLAGS)" LIBS="$(LIBS)" \
	    scripts/check-snippets.sh $(BUILD) $(PNG)

# README.md is a landing page of at most 250 lines, and no page types a
# measured figure by hand (scripts/check-pages.sh); the tables bench/run.sh
# copies into the pages are those of bench/RESULTS.md (bench/run.sh --check).
pages-test:
	@scripts/check-pages.sh
bench-docs-test:
	@bench/run.sh --check $(BUILD)

# The layers are src/'s folders: no file includes, and no object calls,
# above its layer, and no objects call each other round a circle
# (scripts/check-layers.sh; its self-test shows it fails on each).
# The self-test runs the check a dozen times on doctored objects (9 CPU
# seconds): make check-long runs it, which CI runs after make check, so
# that make check stays under two minutes (issue 38).
layers-test: $(OBJS)
	@scripts/check-layers.sh $(BUILD)/obj $(OBJS)
layers-selftest: $(OBJS)
	@CC="$(CC)" scripts/test-check-layers.sh $(BUILD)/obj $(OBJS)

# make check: the builds and the static checks above, then the runs below,
# all prerequisites of check, so that make -jN runs the independent ones
# side by side (issue 38); the Check suite also shares its suites out
# among CHECK_JOBS processes itself (tests/check_main.c), the CPUs online
# by default.  check's own recipe only prints the summary: the time taken,
# the -j hint, and last, alone on its line, "checks: N passed, N failed".
CHECK_JOBS ?= $(call memo,CHECK_JOBS,nproc 2>/dev/null || echo 2)
# Plain make check (the README's command) runs its steps side by side by
# itself, CHECK_JOBS at once: one step at a time took 4 min 56 s of two
# otherwise idle cores, make -j2 check well under half of that (issue 38).
# A -j of the user's wins: GNU make 4.3 applies the command line's after
# the makefile's, and 4.4, which shows it here, is skipped by the filter;
# make -j1 check runs one step at a time.  Only in the top make
# (MAKELEVEL 0): a sub-make that sets -j itself leaves its parent's
# jobserver ("-jN forced in makefile: resetting jobserver mode"), so
# make distcheck's and make sanitize's inner make check share the outer
# make's slots, as many as it was given.
ifneq ($(filter check test check-long,$(MAKECMDGOALS)),)
ifeq ($(MAKELEVEL),0)
ifeq ($(filter -j% --jobs%,$(MAKEFLAGS)),)
MAKEFLAGS += -j$(CHECK_JOBS)
endif
endif
endif
# The time make check started at (seconds), for its summary.
CHECK_T0 := $(shell date +%s)
CHECK_SUMMARY = $(BUILD)/tests/summary
CHECK_RUNS = check-suite check-faultsim fuzz-replay check-examples-run $(if $(filter 1,$(PNG)),mpi-check) \
    bench-smoke-test $(if $(filter 1,$(BENCH_SMOKE)),bench-smoke)

# The suite is the longest step, so it must not start last: make -j hands
# a free slot to the next ready prerequisite in the order it meets them,
# not to the longest, and the suite is ready only once its program is
# linked.  Under make check the other steps wait for that program
# (order-only), so the suite starts as soon as it is built.
CHECK_AFTER_SUITE = layers-test header-test symbols-test man-lint docs-test license-test \
    mutants-list-test links-test snippets-test pages-test bench-docs-test install-test png-free-test \
    version-test abi-test exports-test amalgamation-test check-faultsim fuzz-replay \
    check-examples-run mpi-check mpi-render bench-smoke bench-smoke-test
# The programs the other steps build wait too: make starts a ready
# target only when its pass over check's prerequisites reaches it, and a
# pass blocks on each free slot, so a suite skipped early in the pass
# (its program not yet linked) used to wait for the pass to start every
# example, benchmark and fuzz replay build and most of the other steps:
# make -j2 check started the suite 2 minutes after linking it.
ifneq ($(filter check test,$(MAKECMDGOALS)),)
$(CHECK_AFTER_SUITE) $(FAULTSIM) $(EXAMPLES) $(EXAMPLE_OBJS) $(BENCHES) $(FUZZ_REPLAYS) $(FUZZ_REPLAY_OBJ): | $(TEST_BIN)
endif
# After the suite, the longest steps first (make -j starts them in this
# order), each with what it builds: amalgamation-test compiles the
# library again, and mpi-check and install-test wait on
# mpirun and cmake more than they compute, so they go while the rest
# still has work for the CPUs, not last, alone; so does bench-smoke-test,
# whose POV-Ray sleeps 5 of its 8 seconds (it waited for mpi-check
# once, and ran last: 8 seconds more of make check's wall).
check: deps-check lib check-suite amalgamation-test $(filter mpi-check,$(CHECK_RUNS)) install-test abi-test \
       bench-smoke-test layers-test $(TEST_BIN) $(FAULTSIM) examples $(BENCHES) $(FUZZ_REPLAYS) header-test symbols-test man-lint docs-test license-test mutants-list-test links-test \
       snippets-test pages-test bench-docs-test \
       $(if $(filter 0,$(PNG)),png-free-test) \
       version-test exports-test $(filter-out check-suite mpi-check bench-smoke-test,$(CHECK_RUNS))
	@t=$$(( $$(date +%s) - $(CHECK_T0) )); \
	echo "check: all passed in $$((t / 60))m$$((t % 60))s on $$(nproc 2>/dev/null || echo ?) CPUs$(if $(filter -j%,$(MAKEFLAGS)),, (make -j$(CHECK_JOBS) check runs its steps side by side))"; \
	cat $(CHECK_SUMMARY)

# The Check suite (tests/check_main.c); its summary line goes to
# CHECK_SUMMARY too, which check prints last.  Its workers share the CPUs
# with each other and with make -j's other steps, so a test takes up to a
# few times its time alone: Check's per-test timeouts (4 s by default) are
# stretched by CHECK_TIMEOUT_MULTIPLIER unless CK_TIMEOUT_MULTIPLIER is
# set already (make sanitize and make tsan set 10).
CHECK_TIMEOUT_MULTIPLIER ?= 4
check-suite: $(TEST_BIN)
	@rm -f $(CHECK_SUMMARY)
	CK_TIMEOUT_MULTIPLIER=$${CK_TIMEOUT_MULTIPLIER:-$(CHECK_TIMEOUT_MULTIPLIER)} \
	    RAY_CHECK_JOBS=$(CHECK_JOBS) RAY_CHECK_SUMMARY=$(CHECK_SUMMARY) $(TEST_BIN)

check-faultsim: $(FAULTSIM)
	$(FAULTSIM)

# Runs an example that must fail, under PNG=0, with RAY_ENOTSUP's text.
EXPECT_ENOTSUP = $(CURDIR)/scripts/expect-enotsup.sh
check-examples-run: examples
ifeq ($(PNG),0)
	@echo "check: running the examples (PNG=0: each must fail on its PNG with RAY_ENOTSUP's message)"
	cd $(BUILD) && $(EXPECT_ENOTSUP) examples/hello && $(EXPECT_ENOTSUP) examples/material
	$(EXPECT_ENOTSUP) $(BUILD)/examples/primitives $(BUILD)/primitives.png
	$(EXPECT_ENOTSUP) $(BUILD)/examples/whitted $(BUILD)/whitted.png 16 12 1 2
	$(EXPECT_ENOTSUP) $(BUILD)/examples/cornell $(BUILD)/cornell.png 16 16 1 2
	$(EXPECT_ENOTSUP) $(BUILD)/examples/implicit $(BUILD)/implicit.png 16 10 1 2
	$(EXPECT_ENOTSUP) $(BUILD)/examples/textures doc/cornell.png $(BUILD)/textures.png 16 10 1 2
else
	@echo "check: running the examples (small sizes)"
	cd $(BUILD) && examples/hello >/dev/null && examples/material >/dev/null
	$(BUILD)/examples/picking >/dev/null
	RAY_GAME_FRAMES=10 $(BUILD)/examples/game >/dev/null
	RAY_CONTROLLER_FRAMES=600 $(BUILD)/examples/controller
	$(BUILD)/examples/primitives $(BUILD)/primitives.png >/dev/null
	$(BUILD)/examples/whitted $(BUILD)/whitted.png 64 48 1 2 >/dev/null 2>&1
	$(BUILD)/examples/cornell $(BUILD)/cornell.png 32 32 1 2 >/dev/null 2>&1
	$(BUILD)/examples/implicit $(BUILD)/implicit.png 48 30 1 2 >/dev/null 2>&1
	$(BUILD)/examples/textures doc/cornell.png $(BUILD)/textures.png 48 30 1 2 >/dev/null 2>&1
	@if [ -f data/teapot.bpt ]; then \
	    echo "$(BUILD)/examples/teapot data/teapot.bpt $(BUILD)/teapot.png 48 36 1 2"; \
	    $(BUILD)/examples/teapot data/teapot.bpt $(BUILD)/teapot.png 48 36 1 2 >/dev/null 2>&1; \
	else echo "check: no data/teapot.bpt (scripts/fetch-teapot.sh): teapot example built, not run"; fi
	RAY_CONTROLLER_FRAMES=60 scripts/check-examples.sh $(BUILD)
endif

# The long differential runs at their full counts (issue 38): make check
# runs them reduced (tests/tests.h's test_count: the filter's ten million
# rays as one million, ...), make check-long runs the suites that hold
# them with RAY_CHECK_LONG=1, at the full counts.  CI runs both, so no
# count is lost; doc/TESTING.md lists them.  It also runs the embedding
# checks' steps that make check leaves out (mk/release.mk): five
# compiles of the amalgamation, the CMake subproject's two builds of the
# library (cmake-test: add_subdirectory and FetchContent), and the
# self-tests of the ABI guard and of the layers check, which test those
# checks rather than the library (about 50 CPU seconds together, which
# took make check past two minutes).
# The suites first among the prerequisites, as the longest step: make -j
# starts them beside the embedding steps rather than after them.
CHECK_LONG_SUITES = filter bvh sphere sweep closest
check-long: check-long-suite amalgamation-test-long cmake-test abi-selftest layers-selftest
check-long-suite: deps-check lib $(TEST_BIN)
	CK_TIMEOUT_MULTIPLIER=$${CK_TIMEOUT_MULTIPLIER:-$(CHECK_TIMEOUT_MULTIPLIER)} \
	    RAY_CHECK_LONG=1 RAY_CHECK_SUITES="$(CHECK_LONG_SUITES)" \
	    RAY_CHECK_JOBS=$(CHECK_JOBS) $(TEST_BIN)

# BENCH_QUICK=1 make bench's run as a smoke test, so that no benchmark
# mode breaks unseen (issue 38): every benchmark at its quick sizes,
# writing only bench/RESULTS-quick.md and the -quick plots, which git
# ignores (bench/run.sh), never bench/RESULTS.md or doc/.  About a minute
# of two cores: CI runs it as a step of its own; make check runs it too
# with BENCH_SMOKE=1.  make check runs bench-smoke-test, below, always.
BENCH_SMOKE ?= 0
bench-smoke: deps-bench lib $(BENCHES)
	@echo "bench-smoke: BENCH_QUICK=1 bench/run.sh $(BUILD) (log: $(BUILD)/bench-smoke.log)"
	@BENCH_QUICK=1 bench/run.sh $(BUILD) > $(BUILD)/bench-smoke.log 2>&1 || { \
	    tail -n 40 $(BUILD)/bench-smoke.log; \
	    echo "bench-smoke: BENCH_QUICK=1 bench/run.sh failed (log: $(BUILD)/bench-smoke.log)"; exit 1; }
	@echo "bench-smoke: every benchmark ran (bench/RESULTS-quick.md)"

# make check's smoke of the benchmarks (issue 38): bench/run.sh with
# BENCH_QUICK=smoke runs every program and every mode of the quick run
# once at the smallest sizes (a few rays, pixels and photons, one
# repetition; a small sphere for the bunny's files, so the same with or
# without data/), fails on any program's failure, and writes only
# $(BUILD)/bench/RESULTS-smoke.md and its -smoke plots.  About 3 CPU
# seconds (POV-Ray, where installed, sleeps a few more).  It installs
# nothing: gnuplot and POV-Ray are used where they are.  Under make
# check it waits for mpi-render, which builds mpi_render where the MPI
# tests run, so that bench/mpi.sh's rows run too.
bench-smoke-test: lib $(BENCHES)
	@echo "bench-smoke-test: BENCH_QUICK=smoke bench/run.sh $(BUILD) (log: $(BUILD)/bench-smoke-test.log)"
	@BENCH_QUICK=smoke bench/run.sh $(BUILD) > $(BUILD)/bench-smoke-test.log 2>&1 || { \
	    tail -n 40 $(BUILD)/bench-smoke-test.log; \
	    echo "bench-smoke-test: BENCH_QUICK=smoke bench/run.sh failed (log: $(BUILD)/bench-smoke-test.log)"; exit 1; }
	@echo "bench-smoke-test: every benchmark and mode ran at the smallest sizes ($(BUILD)/bench/RESULTS-smoke.md)"
ifneq ($(filter check test,$(MAKECMDGOALS)),)
bench-smoke-test: | $(if $(filter mpi-check,$(CHECK_RUNS)),mpi-render)
endif

test: check

# ---------------------------------------------------------------- fuzzing
# One target per fuzz/fuzz_*.c (fuzz/fuzz.h: the contracts they check).
# "make check" replays every committed input (fuzz/corpus/<target>, the
# seeds, and fuzz/crashes/<target>, the reproducers) through fuzz/replay.c
# with the suite's compiler and flags; "make fuzz" fuzzes each target for
# FUZZ_SECONDS with clang's libFuzzer, ASan and UBSan (doc/TESTING.md, "Fuzzing").
FUZZ_SECONDS ?= 30
FUZZ_CC      ?= clang
FUZZ_BUILD   ?= build/fuzz
# Extra libFuzzer arguments for every target (e.g. -jobs=4 -workers=4).
FUZZ_ARGS    ?=
# -DFUZZ_CHECK_ALL also checks the contracts of fuzz.h's known defects.
FUZZ_CFLAGS  ?=
FUZZ_SAN = -fsanitize=address,undefined -fno-sanitize-recover=all
FUZZ_LIB_CFLAGS = -O1 -g -fno-omit-frame-pointer $(FUZZ_SAN) \
                  -fsanitize=fuzzer-no-link $(FUZZ_CFLAGS)
# A slow input is a finding too: libFuzzer's own default is 20 minutes.
FUZZ_TIMEOUT ?= 25
# The PNG loader reads files users download: a hostile file must not cost
# more than this (issue 14, defect 4).
FUZZ_FLAGS_fuzz_png ?= -rss_limit_mb=2048 -malloc_limit_mb=512

# fuzz/replay.c (the driver, the same for every target) compiled once,
# not once a target (ten compiles a make check).
FUZZ_REPLAY_OBJ = $(BUILD)/fuzz-replay/obj/replay.o
$(FUZZ_REPLAY_OBJ): fuzz/replay.c fuzz/fuzz.h include/ray.h | deps-build
	@mkdir -p $(@D)
	$(say) CC $<
	$(Q)$(CC) $(ALL_CFLAGS) -Iexamples -Isrc -Itests -c $< -o $@
$(BUILD)/fuzz-replay/%: fuzz/%.c $(FUZZ_REPLAY_OBJ) fuzz/fuzz.h tests/winding_ref.h $(wildcard examples/*.h) $(PRIVATE_HEADERS) $(STATIC)
	@mkdir -p $(@D)
	$(say) CC $<
	$(Q)$(CC) $(ALL_CFLAGS) -Iexamples -Isrc -Itests $(LDFLAGS) -o $@ $< $(FUZZ_REPLAY_OBJ) $(STATIC) $(LIBS)

fuzz-replay: $(FUZZ_REPLAYS)
	@for t in $(FUZZ_TARGETS); do \
	    $(BUILD)/fuzz-replay/$$t fuzz/corpus/$$t fuzz/crashes/$$t || exit 1; \
	done

$(BUILD)/fuzzers/%: fuzz/%.c fuzz/fuzz.h tests/winding_ref.h $(wildcard examples/*.h) $(PRIVATE_HEADERS) $(STATIC)
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -Iexamples -Isrc -Itests -fsanitize=fuzzer $(LDFLAGS) -o $@ $< \
	    $(STATIC) $(LIBS)

fuzz-build: lib $(FUZZ_TARGETS:%=$(BUILD)/fuzzers/%)

# libFuzzer comes with clang (Debian: the libclang-rt-NN-dev package that
# clang depends on); say so plainly when it is missing.
fuzz-probe:
	@mkdir -p $(FUZZ_BUILD)
	@printf '%s\n' '#include <stddef.h>' '#include <stdint.h>' \
	    'int LLVMFuzzerTestOneInput(const uint8_t *d, size_t n);' \
	    'int LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }' \
	    > $(FUZZ_BUILD)/probe.c
	@if ! $(FUZZ_CC) -fsanitize=fuzzer,address,undefined $(FUZZ_BUILD)/probe.c \
	        -o $(FUZZ_BUILD)/probe >/dev/null 2>&1; then \
	    echo "make fuzz: '$(FUZZ_CC) -fsanitize=fuzzer,address,undefined' cannot link:"; \
	    echo "  libFuzzer is unavailable.  Install clang and its runtime (Debian: clang;"; \
	    echo "  libclang-rt-NN-dev has libclang_rt.fuzzer) or set FUZZ_CC=<a clang>."; \
	    exit 1; fi

# Each target runs FUZZ_SECONDS from its committed seeds; new inputs go to
# $(FUZZ_BUILD)/corpus/<target>, crashes to fuzz/crashes/<target>/.  The
# run fails on the first crash, leak, timeout or memory excess.
fuzz: fuzz-probe
	$(MAKE) fuzz-build BUILD=$(FUZZ_BUILD) CC=$(FUZZ_CC) CFLAGS="$(FUZZ_LIB_CFLAGS)"
	$(MAKE) --no-print-directory fuzz-run BUILD=$(FUZZ_BUILD)

fuzz-run:
	@set -e; for t in $(FUZZ_TARGETS); do \
	    mkdir -p $(BUILD)/corpus/$$t $(BUILD)/logs fuzz/crashes/$$t; \
	    case $$t in fuzz_png) extra="$(FUZZ_FLAGS_fuzz_png)";; *) extra=;; esac; \
	    echo "fuzz: $$t for $(FUZZ_SECONDS) s $$extra $(FUZZ_ARGS)"; \
	    if ! $(BUILD)/fuzzers/$$t -max_total_time=$(FUZZ_SECONDS) \
	        -timeout=$(FUZZ_TIMEOUT) -print_final_stats=1 \
	        -artifact_prefix=fuzz/crashes/$$t/ $$extra $(FUZZ_ARGS) \
	        $(BUILD)/corpus/$$t fuzz/corpus/$$t >$(BUILD)/logs/$$t.log 2>&1; then \
	        tail -n 60 $(BUILD)/logs/$$t.log; \
	        echo "fuzz: $$t FAILED: reproducer in fuzz/crashes/$$t/, log $(BUILD)/logs/$$t.log"; \
	        exit 1; fi; \
	    grep -E 'DONE|stat::number_of_executed_units' $(BUILD)/logs/$$t.log; \
	done; echo "fuzz: all targets clean"

# The whole suite again under AddressSanitizer and UndefinedBehaviorSanitizer.
SAN_FLAGS = -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined \
            -fno-sanitize-recover=all
# The sanitizers slow the suite 3 to 15 times (TSan the most), so Check's
# per-test timeout is stretched by CK_TIMEOUT_MULTIPLIER (Check's own
# variable; a shared or loaded machine needs the room).
SAN_TIMEOUT_MULTIPLIER ?= 10
# The float filter's ten million rays (tests/check_filter.c) are a tenth
# of that under the sanitizers, which find memory errors on fewer; the
# other long loops run at make check-long's counts (RAY_CHECK_LONG=1), as
# they did before make check reduced them.  The
# embedding checks (EMBED_CHECK, mk/release.mk) test the build, not the
# code: not repeated under the sanitizers.
SAN_FILTER_RAYS ?= 1000000
sanitize:
	CK_TIMEOUT_MULTIPLIER=$(SAN_TIMEOUT_MULTIPLIER) RAY_FILTER_RAYS=$(SAN_FILTER_RAYS) RAY_CHECK_LONG=1 \
	    $(MAKE) check BUILD=$(BUILD)/asan CFLAGS="$(SAN_FLAGS)" LDFLAGS="$(SAN_FLAGS)" EMBED_CHECK=0

# The suite again built at -O1, with UndefinedBehaviorSanitizer's
# float-cast-overflow check, which gcc's -fsanitize=undefined (make
# sanitize) leaves out and clang's includes (make fuzz found a NaN cell
# count converted to unsigned with it: src/scene/parity.c).  -O1 because
# GCC 12.2 miscompiled the BVH build's binning there and nowhere else
# (src/accel/sah.c, bins4_empty): the sanitizer builds' instrumentation
# hid it, and -O2 does not have it, so no other step saw it.  Cheap
# instrumentation: a make check's time, no timeouts stretched.
O1_FLAGS = -O1 -g -fsanitize=float-cast-overflow -fno-sanitize-recover=all
check-o1:
	$(MAKE) check BUILD=$(BUILD)/o1 CFLAGS="$(O1_FLAGS)" LDFLAGS="$(O1_FLAGS)" EMBED_CHECK=0

# The showcase: the Whitted scene, with a progress bar on stderr.
# The suite again under ThreadSanitizer (the renderer's threads, the
# per-thread contexts and the shared row counter; the threaded BVH build).
TSAN_FLAGS = -O1 -g -fno-omit-frame-pointer -fsanitize=thread
tsan:
	CK_TIMEOUT_MULTIPLIER=$(SAN_TIMEOUT_MULTIPLIER) RAY_FILTER_RAYS=$(SAN_FILTER_RAYS) RAY_CHECK_LONG=1 \
	    $(MAKE) check BUILD=$(BUILD)/tsan CFLAGS="$(TSAN_FLAGS)" LDFLAGS="$(TSAN_FLAGS)" MPI_CHECK=0 EMBED_CHECK=0 \
	    BENCH_EMBREE=0

# ----------------------------------------------------- coverage, mutants
# Line and branch coverage of src/ by what make check runs that exercises
# it (issue 38): the Check suite, the allocation-failure sweep, the fuzz
# replays and the examples' runs, built with gcc's --coverage in a build
# of their own (COVERAGE_BUILD), reported per file by gcovr, and held to a
# floor (scripts/coverage.sh; doc/TESTING.md, "Coverage").  -O1: -O0
# makes the long loops several times slower, -O2 folds away lines that
# then read as never run.  -fprofile-update=atomic: the renderer and the
# BVH build are threaded, and plain counters updated by two threads at
# once come out wrong (gcov's "branch taken -1", which gcovr refuses).
# The counters are zeroed first, so that each run reports itself alone.
# The Check suite runs twice: as make check runs it, and again in a build
# with -DRAY_NO_AVX2 (COVERAGE_BASE_BUILD), as on a CPU without AVX2 (or
# another compiler than GCC, Clang and MSVC on x86): on a CPU with AVX2
# the queries' own copy in intersect.c (the baseline instruction set) and
# the refit's SSE2 leaf run only where the suite compares them with the
# AVX2 copies, while the second run puts every query of the suite, with
# its assertions, through them.  scripts/coverage.sh merges the two.
# Not part of make check (a few minutes more), nor of CI.
COVERAGE_BUILD ?= build/coverage
COVERAGE_BASE_BUILD ?= $(COVERAGE_BUILD)-noavx2
COVERAGE_FLAGS = -O1 -g --coverage -fprofile-update=atomic
COVERAGE_ARGS = BUILD=$(COVERAGE_BUILD) CFLAGS="$(COVERAGE_FLAGS)" LDFLAGS="--coverage" \
    CHECK_TIMEOUT_MULTIPLIER=$(SAN_TIMEOUT_MULTIPLIER)
COVERAGE_BASE_ARGS = BUILD=$(COVERAGE_BASE_BUILD) CFLAGS="$(COVERAGE_FLAGS) -DRAY_NO_AVX2" \
    LDFLAGS="--coverage" CHECK_TIMEOUT_MULTIPLIER=$(SAN_TIMEOUT_MULTIPLIER)
coverage: deps-check
	@scripts/deps.sh $(DEPS_MODE) gcovr
	@mkdir -p $(COVERAGE_BUILD) $(COVERAGE_BASE_BUILD)
	find $(COVERAGE_BUILD) $(COVERAGE_BASE_BUILD) -name '*.gcda' -delete
	$(MAKE) $(COVERAGE_ARGS) coverage-run
	$(MAKE) $(COVERAGE_BASE_ARGS) check-suite
	scripts/coverage.sh $(COVERAGE_BUILD) $(COVERAGE_BASE_BUILD)
coverage-run: check-suite check-faultsim fuzz-replay check-examples-run

# The mutation run (issue 38): each mutant of tests/mutants.txt applied in
# turn to a scratch copy of the tree, the suites that cover its file run
# against it; prints killed or survived for each and the kill rate
# (tests/mutants.sh; doc/TESTING.md, "Mutants").  About an hour of two
# cores for the whole list; MUTANTS="id ..." runs some.  Not part of make
# check, nor of CI.
MUTANTS ?=
mutants: deps-check
	MUTANTS_JOBS=$(CHECK_JOBS) tests/mutants.sh $(MUTANTS)

demo: deps-build lib $(BUILD)/examples/whitted
	$(BUILD)/examples/whitted whitted.png

# The README's caustics picture (examples/caustics.c, 4 million photons).
caustics-png: deps-build lib $(BUILD)/examples/caustics
	RAY_PHOTONS=4000000 $(BUILD)/examples/caustics doc/caustics.png 640 480 16

# ---------------------------------------------------------------- Windows
# make windows-check (doc/PLATFORMS.md): the library (static, and a DLL
# with its import library), the Check suite, the fault sweep and the
# examples, cross-built with MinGW-w64 and run under Wine
# (scripts/windows-check.sh; about 8 minutes on two cores from a clean
# build/windows*, 3 of them the runs).  Check, libpng and zlib for MinGW come from
# Debian's source packages (scripts/windows-deps.sh), built once into
# WIN_DEPS.  The same sources and warnings as here, -Werror by default;
# the library is src/core/platform_win32.c's branch, never winpthreads
# (only the tests and examples, which use pthreads themselves, link it).
WIN_HOST   ?= x86_64-w64-mingw32
WIN_CC     ?= $(WIN_HOST)-gcc
WIN_AR     ?= $(WIN_HOST)-ar
WIN_CFLAGS ?= -O2 -g -Werror
WIN_BUILD  ?= build/windows
WIN_DEPS   ?= build/windows-deps
# C99 and no contraction as here; MinGW's C99 printf (core/vec.h).
WIN_STD = -std=c99 -ffp-contract=off -fno-fast-math -D__USE_MINGW_ANSI_STDIO=1
WIN_ALL_CFLAGS = $(WARN) -Iinclude $(WIN_CFLAGS) $(WIN_STD) -isystem $(WIN_DEPS)/include
WIN_SRCS = $(filter-out src/image/png_none.c,$(wildcard src/*/*.c))
WIN_OBJS = $(WIN_SRCS:src/%.c=$(WIN_BUILD)/obj/%.o)
WIN_DLL_OBJS = $(WIN_SRCS:src/%.c=$(WIN_BUILD)/dllobj/%.o)
WIN_STATIC = $(WIN_BUILD)/libray.a
WIN_DLL = $(WIN_BUILD)/libray.dll
WIN_IMPLIB = $(WIN_BUILD)/libray.dll.a
WIN_TEST = $(WIN_BUILD)/tests/check_ray.exe
WIN_FAULTSIM = $(WIN_BUILD)/tests/faultsim.exe
WIN_EXAMPLES = $(patsubst examples/%.c,$(WIN_BUILD)/examples/%.exe,$(filter-out examples/mpi_render.c,$(wildcard examples/*.c)))
WIN_LIBS = -L$(WIN_DEPS)/lib -lpng -lz
# The tests and examples link everything but the system DLLs statically
# (libgcc, winpthreads), so Wine needs no MinGW DLL beside them.
WIN_EXE_LIBS = -static -lpthread
WIN_FAULT_WRAPS = malloc calloc realloc free png_image_write_to_memory \
    ray__thread_start

# Check without fork (Windows) does not mark its failure call noreturn (it
# longjmps back to the runner), so GCC sees a test's variables read after
# a failed assertion as maybe uninitialised; the Linux build, where it is
# noreturn, checks the same code.
WIN_TEST_CFLAGS = -Wno-maybe-uninitialized

$(WIN_DEPS)/stamp: scripts/windows-deps.sh
	@scripts/windows-deps.sh $(WIN_DEPS)

# Objects of the static library, and of the DLL (RAY_DLL: ray.h's
# dllexport, so that the DLL exports the API and nothing else).
$(WIN_BUILD)/obj/%.o: src/%.c $(PRIVATE_HEADERS) include/ray.h | $(WIN_DEPS)/stamp
	@mkdir -p $(@D)
	$(WIN_CC) $(WIN_ALL_CFLAGS) -Isrc -DRAY_BUILD \
	    $(if $(filter $(AVX2_SRCS),$<),-mavx2) -c $< -o $@
$(WIN_BUILD)/dllobj/%.o: src/%.c $(PRIVATE_HEADERS) include/ray.h | $(WIN_DEPS)/stamp
	@mkdir -p $(@D)
	$(WIN_CC) $(WIN_ALL_CFLAGS) -Isrc -DRAY_BUILD -DRAY_DLL \
	    $(if $(filter $(AVX2_SRCS),$<),-mavx2) -c $< -o $@

$(WIN_STATIC): $(WIN_OBJS)
	rm -f $@
	$(WIN_AR) rcs $@ $(WIN_OBJS)

# libpng and zlib inside (static), libgcc too: the DLL needs only
# KERNEL32.dll and msvcrt.dll (windows-check checks it).
$(WIN_DLL) $(WIN_IMPLIB): $(WIN_DLL_OBJS)
	$(WIN_CC) $(WIN_CFLAGS) -shared -static-libgcc -o $(WIN_DLL) \
	    $(WIN_DLL_OBJS) -Wl,--out-implib,$(WIN_IMPLIB) $(WIN_LIBS)

$(WIN_TEST): $(TEST_SRCS) tests/check_main.c $(wildcard tests/*.h) $(wildcard examples/*.h) bench/bench.h $(WIN_STATIC)
	@mkdir -p $(@D)
	$(WIN_CC) $(WIN_ALL_CFLAGS) $(WIN_TEST_CFLAGS) -Isrc -Iexamples -Ibench -Itests -DRAY_TEST_PNG=1 \
	    -o $@ tests/check_main.c $(TEST_SRCS) $(WIN_STATIC) -lcheck $(WIN_LIBS) \
	    -lpsapi $(WIN_EXE_LIBS) -Wl,--wrap=tcase_fn_start

$(WIN_FAULTSIM): tests/faultsim.c tests/testkit.h tests/tempfiles.h examples/common.h include/ray.h $(WIN_STATIC)
	@mkdir -p $(@D)
	$(WIN_CC) $(WIN_ALL_CFLAGS) -Isrc -Iexamples -DRAY_TEST_PNG=1 -o $@ \
	    tests/faultsim.c $(WIN_STATIC) $(WIN_LIBS) $(WIN_EXE_LIBS) \
	    $(patsubst %,-Wl$(comma)--wrap=%,$(WIN_FAULT_WRAPS))

# The examples use the DLL (through its import library, RAY_DLL for
# dllimport); a copy of it sits beside them, where Windows looks first.
$(WIN_BUILD)/examples/%.exe: examples/%.c $(wildcard examples/*.h) $(WIN_IMPLIB)
	@mkdir -p $(@D)
	cp $(WIN_DLL) $(@D)/
	$(WIN_CC) $(WIN_ALL_CFLAGS) -DRAY_DLL -o $@ $< $(WIN_IMPLIB) $(WIN_EXE_LIBS)

# The C runtime's math, probed on both sides (scripts/libm-probe.c).
$(WIN_BUILD)/tools/libm-probe.exe: scripts/libm-probe.c | $(WIN_DEPS)/stamp
	@mkdir -p $(@D)
	$(WIN_CC) $(WIN_ALL_CFLAGS) -o $@ $< $(WIN_EXE_LIBS)

windows-build: $(WIN_STATIC) $(WIN_DLL) $(WIN_TEST) $(WIN_FAULTSIM) $(WIN_EXAMPLES) \
    $(WIN_BUILD)/tools/libm-probe.exe

# The native side: the examples render the images the Windows ones must
# match, the shared library's exports are the DLL's, and two tools
# (scripts/imgdiff.c measures a difference; scripts/libm-probe.c).
$(BUILD)/tools/imgdiff: scripts/imgdiff.c | deps-build
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) $(PNG_CFLAGS) $(LDFLAGS) -o $@ $< $(PNG_LIBS)
$(BUILD)/tools/libm-probe: scripts/libm-probe.c
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) $(LDFLAGS) -o $@ $< -lm -lpthread

windows-check: lib examples $(BUILD)/tools/imgdiff $(BUILD)/tools/libm-probe
	@test "$(PNG)" = 1 || { echo "windows-check: needs the native build with libpng (PNG=1), to compare pictures"; exit 1; }
	@$(MAKE) --no-print-directory windows-build
	@WIN_HOST=$(WIN_HOST) WINDOWS_RECORD=$(WINDOWS_RECORD) \
	    scripts/windows-check.sh $(WIN_BUILD) $(BUILD)

# ---------------------------------------------------------------- install
# libray.pc and the CMake package name their paths relative to where they
# are installed (pkg-config's ${prefix}, CMake's CMAKE_CURRENT_LIST_DIR),
# so a moved install tree still works (make install-test moves one).
# A directory outside PREFIX stays absolute.
rel_to_prefix = $(if $(filter $(PREFIX)/%,$(1)),$(2)/$(patsubst $(PREFIX)/%,%,$(1)),$(1))
# From CMAKEDIR up to PREFIX: one ".." per component of CMAKEDIR below it
# (lib/cmake/libray: ../../..).
space := $() $()
CMAKE_UP = $(subst $(space),/,$(patsubst %,..,$(subst /, ,$(patsubst $(PREFIX)/%,%,$(CMAKEDIR)))))
# The pointer size the library was built for, which a CMake project must share.
SIZEOF_VOID_P = $(call memo,SIZEOF_VOID_P,echo __SIZEOF_POINTER__ | $(CC) -E -P - 2>/dev/null | tail -n 1)
CMAKE_PREFIX = $(if $(filter $(PREFIX)/%,$(CMAKEDIR)),$${CMAKE_CURRENT_LIST_DIR}/$(CMAKE_UP),$(PREFIX))

# A program linked with `pkg-config --libs libray` must find libray.so.1
# when it runs.  The dynamic loader searches its default directories
# (/lib, /usr/lib, their lib64 and multiarch forms) by itself; for any
# other LIBDIR (/usr/local/lib included, which Debian's loader knows only
# through the ldconfig cache, and /opt or $HOME prefixes, which it does
# not know at all) libray.pc's Libs carries -Wl,-rpath,${libdir}, so the
# program runs without LD_LIBRARY_PATH (a moved install through
# pkg-config --define-prefix too: ${libdir} follows ${prefix}).
# PC_RPATH=0 leaves it out (a distribution package), PC_RPATH=1 forces it.
MULTIARCH = $(call memo,MULTIARCH,$(CC) -print-multiarch 2>/dev/null)
LOADER_DIRS = /lib /usr/lib /lib64 /usr/lib64 \
    $(if $(MULTIARCH),/lib/$(MULTIARCH) /usr/lib/$(MULTIARCH))
PC_RPATH ?= $(if $(filter $(patsubst %/,%,$(LIBDIR)),$(LOADER_DIRS)),0,1)
# ldconfig refreshes the loader's cache after install and uninstall when
# it applies: run as root, into the live system (DESTDIR empty); a
# package (DESTDIR set) leaves it to its installer, and a user without
# root relies on the rpath above.
LDCONFIG ?= ldconfig
RUN_LDCONFIG = if [ -z "$(DESTDIR)" ] && [ "$$(id -u)" = 0 ] && \
        command -v $(LDCONFIG) >/dev/null 2>&1; then \
        echo "$(LDCONFIG)"; $(LDCONFIG) || exit 1; \
    elif [ -z "$(DESTDIR)" ]; then \
        echo "libray: ldconfig not run (not root, or not found): programs find $(LIBDIR)/libray.so.$(SOMAJOR) through libray.pc's rpath$(if $(filter 0,$(PC_RPATH)), (none: PC_RPATH=0; run ldconfig as root))"; \
    fi

# pkg-config --static --cflags --libs libray links libray.a, not
# libray.so (libray.pc.in: -Wl,-Bstatic before -lray, -Wl,-Bdynamic after
# it), where the linker takes -Bstatic: GNU ld, gold and lld do, Apple's
# ld does not (PC_BSTATIC=0 there: --static then links libray.so, as
# pkg-config has no other way to choose the archive).
PC_BSTATIC ?= $(if $(findstring darwin,$(call memo,CC_MACHINE,$(CC) -dumpmachine 2>/dev/null)),0,1)

libray.pc:
	@mkdir -p $(BUILD)
	sed -e 's|@PREFIX@|$(PREFIX)|' \
	    -e 's|@LIBDIR@|$(call rel_to_prefix,$(LIBDIR),$${prefix})|' \
	    -e 's|@INCLUDEDIR@|$(call rel_to_prefix,$(INCLUDEDIR),$${prefix})|' \
	    -e 's|@VERSION@|$(VERSION)|' \
	    -e 's|@RPATH@|$(if $(filter 1,$(PC_RPATH)), -Wl$(comma)-rpath$(comma)$${libdir})|' \
	    $(if $(filter 1,$(PNG)),-e 's|@PNG_REQUIRES@|libpng|',-e '/@PNG_REQUIRES@/d') \
	    $(if $(filter 1,$(PC_BSTATIC)),-e 's|@BDYNAMIC@|-Wl$(comma)-Bdynamic |',-e 's|@BDYNAMIC@||' -e '/^Cflags.private:/d') \
	    libray.pc.in > $(BUILD)/libray.pc

# Written here, not by CMake: installing needs no CMake.
cmake-config:
	@mkdir -p $(BUILD)/cmake
	sed -e 's|@PREFIX@|$(CMAKE_PREFIX)|' \
	    -e 's|@LIBDIR@|$(call rel_to_prefix,$(LIBDIR),$${_libray_prefix})|' \
	    -e 's|@INCLUDEDIR@|$(call rel_to_prefix,$(INCLUDEDIR),$${_libray_prefix})|' \
	    -e 's|@VERSION@|$(VERSION)|' -e 's|@SOMAJOR@|$(SOMAJOR)|' \
	    -e 's|@PNG@|$(PNG)|' \
	    cmake/librayConfig.cmake.in > $(BUILD)/cmake/librayConfig.cmake
	sed -e 's|@VERSION@|$(VERSION)|' -e 's|@MAJOR@|$(word 1,$(subst ., ,$(VERSION)))|' \
	    -e 's|@SIZEOF_VOID_P@|$(SIZEOF_VOID_P)|' \
	    cmake/librayConfigVersion.cmake.in > $(BUILD)/cmake/librayConfigVersion.cmake

# The directories install makes that did not exist are listed in
# DOCDIR/installed-dirs, so that uninstall removes them (when empty) and
# no other (scripts/install-dirs.sh); DOCDIR and CMAKEDIR are ours anyway.
INSTALL_DIRS = $(LIBDIR) $(INCLUDEDIR) $(PKGCONFIGDIR) $(CMAKEDIR) \
    $(MANDIR)/man3 $(MANDIR)/man7 $(DOCDIR)
DIRS_LIST = $(DOCDIR)/installed-dirs

install: lib libray.pc cmake-config
	@scripts/install-dirs.sh create "$(DESTDIR)" "$(PREFIX)" "$(DIRS_LIST)" \
	    $(INSTALL_DIRS)
	install -m 644 $(STATIC) $(DESTDIR)$(LIBDIR)/libray.a
	install -m 755 $(SHARED) $(DESTDIR)$(LIBDIR)/libray.so.$(VERSION)
	ln -sf libray.so.$(VERSION) $(DESTDIR)$(LIBDIR)/libray.so.$(SOMAJOR)
	ln -sf libray.so.$(VERSION) $(DESTDIR)$(LIBDIR)/libray.so
	install -m 644 include/ray.h $(DESTDIR)$(INCLUDEDIR)/ray.h
	install -m 644 $(BUILD)/libray.pc $(DESTDIR)$(PKGCONFIGDIR)/libray.pc
	install -m 644 $(BUILD)/cmake/librayConfig.cmake \
	    $(BUILD)/cmake/librayConfigVersion.cmake $(DESTDIR)$(CMAKEDIR)/
	install -m 644 man/man3/*.3 $(DESTDIR)$(MANDIR)/man3/
	install -m 644 man/man7/*.7 $(DESTDIR)$(MANDIR)/man7/
	install -m 644 LICENSE $(DESTDIR)$(DOCDIR)/LICENSE
	@set -e; for l in $(MLINKS); do \
	    ln -sf $${l%%:*}.3 $(DESTDIR)$(MANDIR)/man3/$${l##*:}.3; done
	@$(RUN_LDCONFIG)

uninstall:
	rm -f $(DESTDIR)$(LIBDIR)/libray.a $(DESTDIR)$(LIBDIR)/libray.so \
	    $(DESTDIR)$(LIBDIR)/libray.so.$(SOMAJOR) \
	    $(DESTDIR)$(LIBDIR)/libray.so.$(VERSION) \
	    $(DESTDIR)$(INCLUDEDIR)/ray.h $(DESTDIR)$(PKGCONFIGDIR)/libray.pc \
	    $(DESTDIR)$(CMAKEDIR)/librayConfig.cmake \
	    $(DESTDIR)$(CMAKEDIR)/librayConfigVersion.cmake
	@echo "rm -f the man pages and their links in $(DESTDIR)$(MANDIR)/man3 and man7 (one rm)"
	@rm -f $(addprefix $(DESTDIR)$(MANDIR)/man3/,$(notdir $(wildcard man/man3/*.3)) \
	    $(addsuffix .3,$(foreach l,$(MLINKS),$(lastword $(subst :, ,$(l)))))) \
	    $(addprefix $(DESTDIR)$(MANDIR)/man7/,$(notdir $(wildcard man/man7/*.7)))
	rm -f $(DESTDIR)$(DOCDIR)/LICENSE
	@scripts/install-dirs.sh remove "$(DESTDIR)" "$(PREFIX)" "$(DIRS_LIST)" \
	    $(DOCDIR) $(CMAKEDIR)
	@$(RUN_LDCONFIG)

# A staged install moved elsewhere still builds a program through
# pkg-config --define-prefix and through CMake (when cmake is installed);
# uninstall leaves an empty prefix and keeps directories it did not make.
install-test: $(STATIC) $(SHARED)
	@CC="$(CC)" CFLAGS="$(CFLAGS)" LDFLAGS="$(LDFLAGS)" \
	    scripts/check-install.sh "$(MAKE)" "$(BUILD)" "$(PNG)"

# make PNG=0: neither library needs libpng (no NEEDED entry, no png_*
# reference left undefined).
png-free-test: $(STATIC) $(SHARED)
	@if objdump -p $(SHARED) | grep NEEDED | grep -i png; then \
	    echo "png-free-test: $(SHARED) needs libpng"; exit 1; fi
	@if nm -u $(STATIC) | grep ' U png_'; then \
	    echo "png-free-test: $(STATIC) refers to libpng"; exit 1; fi
	@echo "png-free-test: $(SHARED) NEEDED:" \
	    $$(objdump -p $(SHARED) | awk '$$1 == "NEEDED" {print $$2}')

# The amalgamation, the CMake subproject, the ABI guard, the version,
# make dist and make distcheck.
include mk/release.mk

clean:
	rm -rf $(BUILD) whitted.png hello.png cornell.png primitives.png material.png
