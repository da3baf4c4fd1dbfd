# SPDX-License-Identifier: MIT
# release.mk -- included by the Makefile: how libray is shipped and
# embedded besides make install (doc/EMBEDDING.md), and the checks that
# hold each to the Makefile's build, run by make check (cmake-test and
# the ABI guard's self-test by make check-long, which CI runs too):
#
#   make amalgamation   $(BUILD)/amalgamation/libray.c and ray.h, the whole
#                       library in one translation unit (amalgamation-test)
#   CMakeLists.txt      libray::libray for add_subdirectory and
#                       FetchContent (cmake-test)
#   abi/libray.abi      the public ABI, compared with the shared library
#                       (abi-test); make abi-baseline records it anew
#   the API's size      at most EXPORTS_MAX exported functions
#                       (exports-test)
#   the version         set in include/ray.h alone (version-test)
#   make dist           libray-VERSION.tar.gz; make distcheck runs make
#                       check in it, unpacked in a temporary directory
#
# EMBED_CHECK=0 skips cmake-test, amalgamation-test and the ABI guard's
# self-test, which test the build rather than the code: the sanitizer
# runs pass it, and it is the default under AMALGAMATION=1 (they compare
# the amalgamation with the per-file build).

EMBED_CHECK ?= $(if $(filter 1,$(AMALGAMATION)),0,1)

# CMake and libabigail's tools, installed by make check as its other
# packages are (scripts/deps.sh); after deps-check, so that two apt-get
# never run at once.
deps-embed: deps-check
	@scripts/deps.sh $(DEPS_MODE) cmake abigail

print-srcs:
	@echo $(SRCS)

print-version:
	@echo $(VERSION) $(SOMAJOR)

# ----------------------------------------------------------- amalgamation
# scripts/amalgamate.c reads every source (both PNG files: RAY_PNG
# chooses, 0 by default, so that the file needs no libpng) and inlines
# the private headers; scripts/amalgamation-prologue.h comes first.  A new
# source file in src/<layer>/ needs no line here.
AMALGAMATE = $(BUILD)/tools/amalgamate
AMALG_SRCS = $(sort $(wildcard src/*/*.c))
AMALG_IF = -if src/image/png.c RAY_PNG -if src/image/png_none.c '!RAY_PNG'

# A build tool: the library's warnings, not CFLAGS' sanitizers (LeakSanitizer
# would fail a generator that leaves its memory to exit).
$(AMALGAMATE): scripts/amalgamate.c
	@mkdir -p $(@D)
	$(CC) -std=c99 -O2 $(WARN) $(filter -Werror,$(CFLAGS)) -o $@ $<

$(AMALG_DIR)/libray.c: $(AMALGAMATE) $(AMALG_SRCS) $(PRIVATE_HEADERS) \
                       scripts/amalgamation-prologue.h include/ray.h
	@mkdir -p $(@D)
	sed 's/@VERSION@/$(VERSION)/' scripts/amalgamation-prologue.h \
	    > $(AMALG_DIR)/prologue.h
	$(AMALGAMATE) -o $@.tmp -I src -p $(AMALG_DIR)/prologue.h $(AMALG_IF) \
	    $(AMALG_SRCS)
	mv $@.tmp $@

$(AMALG_DIR)/ray.h: include/ray.h
	@mkdir -p $(@D)
	cp include/ray.h $@

amalgamation: $(AMALG_DIR)/libray.c $(AMALG_DIR)/ray.h

# The object both libraries are made of under AMALGAMATION=1: built as
# the objects are (warnings, CFLAGS, STD_CFLAGS), with the internal
# functions external for the tests (RAY_AMALGAMATION_INTERNALS).
$(AMALG_DIR)/libray.o: $(AMALG_DIR)/libray.c $(AMALG_DIR)/ray.h \
                       $(BUILD)/png.config | deps-build
	$(CC) $(WARN) -I$(AMALG_DIR) $(CFLAGS) $(STD_CFLAGS) -fPIC \
	    -fvisibility=hidden -DRAY_PNG=$(PNG) -DRAY_AMALGAMATION_INTERNALS \
	    $(PNG_CFLAGS) -c $< -o $@

ifeq ($(EMBED_CHECK),1)
# scripts/check-amalgamation.sh: the documented command alone; gcc and
# clang with the library's warnings, the pragmas doing -ffp-contract=off's
# work; the examples linked with it, their pictures against the Makefile's.
# Under make check, only the steps that check the pages' commands and the
# pictures (AMALG_PART=check); the five other whole-library compiles (gcc
# and clang, -mavx2) run in make check-long (amalgamation-test-long), which
# CI runs too (issue 38).  make amalgamation-test alone runs every step.
AMALG_PART ?= $(if $(filter check test,$(MAKECMDGOALS)),check,all)
AMALG_TEST = CC="$(CC)" CFLAGS="$(CFLAGS)" LDFLAGS="$(LDFLAGS)" WARN="$(WARN)" \
    ALL_CFLAGS="$(ALL_CFLAGS)" PNG_CFLAGS="$(PNG_CFLAGS)" LIBS="$(LIBS)" \
    EXAMPLE_OBJ="$(EXAMPLE_OBJ)" scripts/check-amalgamation.sh $(AMALG_DIR) $(BUILD) $(PNG)
amalgamation-test: amalgamation $(EXAMPLES) $(EXAMPLE_OBJS) | deps-embed
	@AMALG_PART=$(AMALG_PART) $(AMALG_TEST)
amalgamation-test-long: amalgamation $(BUILD)/examples/whitted | deps-embed
	@AMALG_PART=long $(AMALG_TEST)

# ------------------------------------------------------- CMake subproject
# scripts/check-cmake.sh: tests/cmake-consumer through add_subdirectory
# and FetchContent; the sources and flags against the Makefile's; the
# picture against the Makefile's.
# Both builds of the library (CMAKE_PART=add_subdirectory or
# FetchContent, given by hand, picks one): make check-long runs it, which CI runs after make check, not
# make check itself, whose two minutes it took 30 CPU seconds of (issue
# 38).
CMAKE_TEST = CC="$(CC)" CFLAGS="$(CFLAGS)" LDFLAGS="$(LDFLAGS)" \
    AVX2_CFLAGS="$(AVX2_CFLAGS)" VERSION="$(VERSION)" SOMAJOR="$(SOMAJOR)" \
    scripts/check-cmake.sh "$(MAKE)" $(BUILD) $(PNG)
cmake-test: $(BUILD)/examples/whitted | deps-embed
	@$(CMAKE_TEST)
else
amalgamation-test amalgamation-test-long cmake-test:
	@echo "check: $@ skipped (EMBED_CHECK=$(EMBED_CHECK))"
endif

# ---------------------------------------------------------------- the ABI
# abi/libray.abi is the public ABI (functions, the types they reach, the
# soname, the version nodes) as abidw records it; scripts/check-abi.sh
# compares the shared library with it (abidiff) and fails on any change,
# with the report.  A change that is meant is recorded in the same commit
# with make abi-baseline (doc/DESIGN.md, "Versions and ABI": which
# version and soname it then needs).  The self-test
# (scripts/test-check-abi.sh) shows the guard failing on a reordered
# struct, a grown struct, a removed and an added function.
ABI_BASELINE = abi/libray.abi
# The ray.h the library was compiled with: the amalgamation's copy under
# AMALGAMATION=1.
ABI_HEADERS = $(if $(filter 1,$(AMALGAMATION)),$(AMALG_DIR),include)

abi-test: $(SHARED) | deps-embed
	@scripts/check-abi.sh compare $(SHARED) $(ABI_HEADERS) $(ABI_BASELINE)

# The self-test compiles the amalgamation three times (11 CPU seconds):
# make check-long runs it, not make check (issue 38).
abi-selftest: $(if $(filter 1,$(EMBED_CHECK)),amalgamation) | deps-embed
	@if [ "$(EMBED_CHECK)" = 1 ]; then \
	    CC="$(CC)" LDFLAGS="$(LDFLAGS)" \
	    scripts/test-check-abi.sh $(AMALG_DIR) $(ABI_BASELINE) $(SOMAJOR); \
	else echo "check: $@ skipped (EMBED_CHECK=$(EMBED_CHECK))"; fi

abi-baseline: $(SHARED) | deps-embed
	@scripts/check-abi.sh record $(SHARED) $(ABI_HEADERS) $(ABI_BASELINE)

# ------------------------------------------------------- the API's size
# libray 1.0 exports at most 100 functions (issue 37): a minimal API, as
# SQLite's, Lua's and Embree's are, without losing a capability.
# exports-test counts the functions the shared library exports (nm -D:
# defined text symbols named ray_*, the ray__ internals aside, which
# -fvisibility=hidden keeps local and symbols-test watches) and fails
# above EXPORTS_MAX, naming them.  A function added past the limit must
# replace one, fold into one (an options pointer, NULL for the
# defaults), or become an internal ray__ function the tests reach.
# EXPORTS_MAX is the count today, 100, issue 37's limit: the options and
# the batches are folded into ray_intersect, ray_occluded and the _batch
# calls, and the four ray_overlap_* calls into ray_overlap_shape and its
# _all form; ray_scene_set_progress is the hundredth.
EXPORTS_MAX ?= 100
exports-test: $(SHARED)
	@n=$$(nm -D --defined-only $(SHARED) | awk '$$2 == "T" {sub(/@.*/, "", $$3); print $$3}' | \
	    grep '^ray_[^_]' | sort -u | wc -l); \
	if [ "$$n" -gt $(EXPORTS_MAX) ]; then \
	    echo "exports-test: $$n exported functions, more than EXPORTS_MAX ($(EXPORTS_MAX)):"; \
	    nm -D --defined-only $(SHARED) | awk '$$2 == "T" {sub(/@.*/, "", $$3); print "  " $$3}' | sort -u; \
	    exit 1; \
	fi; \
	echo "exports-test: $$n exported functions, at most $(EXPORTS_MAX)"

# ------------------------------------------------------------ the version
# scripts/check-version.sh: ray.h's numbers as the compiler reads them,
# the linked library's, the Makefile's, CMake's, libray.pc's, the CMake
# package's, the soname, the amalgamation's and CHANGELOG.md's newest
# release agree.
version-test: $(STATIC) $(SHARED) $(AMALG_DIR)/libray.c | deps-embed
	@CC="$(CC)" CFLAGS="$(CFLAGS)" LDFLAGS="$(LDFLAGS)" LIBS="$(LIBS)" \
	    scripts/check-version.sh "$(MAKE)" $(BUILD)

# ---------------------------------------------------------------- release
# make dist: libray-VERSION.tar.gz of the files git tracks (the sources,
# headers, build files, tests and their committed inputs, examples,
# benchmarks with their recorded figures, which doc/BENCHMARKS.md cites,
# documentation with its pictures, which README.md shows and the tests
# read), without what only the repository uses (.ci/, .gitignore):
# never build output or fetched data (data/), which git does not track.
DIST = libray-$(VERSION)
DIST_DIR = $(BUILD)/dist
# Where the tarball goes (scripts/check-cmake.sh puts one beside the
# project that fetches it, as doc/EMBEDDING.md's FetchContent block has it).
DIST_TARBALL = $(DIST).tar.gz

dist:
	@if ! git rev-parse --is-inside-work-tree >/dev/null 2>&1; then \
	    echo "make dist: needs a git checkout (it packs what git ls-files lists)"; \
	    exit 1; fi
	@rm -rf $(DIST_DIR) && mkdir -p $(DIST_DIR)/$(DIST)
	@git ls-files | grep -v -e '^\.ci/' -e '^\.gitignore$$' | \
	    while IFS= read -r f; do [ ! -f "$$f" ] || echo "$$f"; done \
	    > $(DIST_DIR)/files
	tar -cf - -T $(DIST_DIR)/files | tar -C $(DIST_DIR)/$(DIST) -xf -
	tar -C $(DIST_DIR) -cf - $(DIST) | gzip -9 -n > $(DIST_TARBALL)
	@echo "dist: $(DIST_TARBALL): $$(wc -l < $(DIST_DIR)/files) files, $$(wc -c < $(DIST_TARBALL)) bytes"

# make check in the tarball, unpacked in a temporary directory: it holds
# all make check needs, and nothing built.  Without the embedding checks
# (EMBED_CHECK=0: cmake-test, amalgamation-test, the ABI guard's
# self-test), which compile the whole library four more times and test
# the build, not the tarball's contents: make check-long's cmake-test
# builds the tarball itself through FetchContent (scripts/check-cmake.sh),
# and the amalgamation is still generated here (version-test reads it),
# from the same sources steps 1 and 2 of .ci/run compile (issue 38).
distcheck: dist
	@if tar -tzf $(DIST).tar.gz | grep -E '^$(DIST)/(build|data)/|\.o$$'; then \
	    echo "distcheck: $(DIST).tar.gz holds build output or fetched data"; \
	    exit 1; fi
	@set -e; tmp=$$(mktemp -d "$${TMPDIR:-/tmp}/libray-distcheck.XXXXXX"); \
	trap 'rm -rf "$$tmp"' EXIT; \
	tar -C "$$tmp" -xzf $(DIST).tar.gz; \
	echo "distcheck: make check in $$tmp/$(DIST)"; \
	$(MAKE) -C "$$tmp/$(DIST)" check EMBED_CHECK=0; \
	echo "distcheck: $(DIST).tar.gz unpacked, built and checked: ready to ship"
