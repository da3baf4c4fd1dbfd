#!/bin/sh
# SPDX-License-Identifier: MIT
# check-cmake.sh MAKE BUILD PNG -- make cmake-test (part of make check): libray
# as a CMake subproject (CMakeLists.txt) builds what the Makefile builds.
#
# tests/cmake-consumer, a project using libray as a game would, is
# copied and configured and built twice with CMake, each time taking in
# libray through doc/EMBEDDING.md's block for it, as written (read from
# the page by scripts/doc-block.sh, so that the page cannot drift):
#
#   add_subdirectory  this tree linked at third_party/libray; libray::libray
#                     static (CMake's default), LIBRAY_PNG as the
#                     Makefile's PNG; its examples/whitted.c renders the
#                     picture make check renders, and the two files are
#                     compared with cmp;
#   FetchContent      the make dist tarball beside the project's
#                     CMakeLists.txt (this tree packed as it is where it is
#                     no git checkout: make distcheck unpacked it), with
#                     BUILD_SHARED_LIBS: libray.so.VERSION with the soname
#                     libray.so.MAJOR, exporting ray_* alone; LIBRAY_PNG
#                     left at its default, which must be on exactly where
#                     libpng is found (pkg-config --exists libpng), the
#                     configure log saying so, and libray.so then needing
#                     libpng.
#
# Each time the consumer runs (it renders a sphere and checks the linked
# library's version against the header's), and the library CMake built is
# held to the Makefile's: the same source files (make print-srcs, the
# Makefile's SRCS for that PNG setting, against libray-sources.txt, which
# CMakeLists.txt writes), and in
# compile_commands.json every library file compiled with -std=c99,
# -ffp-contract=off, -fno-fast-math, -D_POSIX_C_SOURCE=200809L and
# -fvisibility=hidden, and the AVX2 copies alone (src/query/intersect_avx2.c,
# src/scene/refit_avx2.c: the Makefile's AVX2_SRCS) with the Makefile's
# AVX2 flag (AVX2_CFLAGS, empty off x86).
#
# CC, CFLAGS, LDFLAGS, AVX2_CFLAGS, VERSION and SOMAJOR come from
# the environment (the Makefile's).  Without cmake, says so and passes
# (.ci/run installs cmake).
set -eu
make=$1 build=$2 png=$3
: "${CC:=cc}" "${CFLAGS:=}" "${LDFLAGS:=}" "${AVX2_CFLAGS:=}"
top=$(pwd)

if ! command -v cmake >/dev/null 2>&1; then
    echo "cmake-test: no cmake here: skipped (.ci/run installs cmake)"
    exit 0
fi
tmp=$(mktemp -d "${TMPDIR:-/tmp}/libray-cmake-test.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "cmake-test: $*" >&2; exit 1; }
jobs=$(nproc 2>/dev/null || echo 2)
# CMAKE_PART, which consumer is built: "add_subdirectory" or
# "FetchContent" alone, by hand; "all", the default and what make
# cmake-test (make check-long's) runs, both.
part=${CMAKE_PART:-all}
want() {
    case $part in
    all|"$1") return 0 ;;
    esac
    return 1
}

# The Makefile's picture, rendered here at the size make check uses.
"$build/examples/whitted" "$tmp/make.png" 64 48 1 2 >/dev/null 2>&1 ||
    [ "$png" = 0 ] || fail "$build/examples/whitted failed"

# The Makefile's sources under PNG=$1, one a line.
make_sources() {
    $make --no-print-directory -s print-srcs PNG="$1" | tr ' ' '\n' |
        sed '/^$/d' | sort
}

# make_project MODE DIR: the consumer copied to DIR-src, with MODE's block of
# doc/EMBEDDING.md in libray.cmake and what the block takes in beside it.
make_project() {
    src=$2-src
    mkdir -p "$src"
    cp "$top/tests/cmake-consumer/CMakeLists.txt" \
       "$top/tests/cmake-consumer/main.c" "$src/"
    "$top/scripts/doc-block.sh" "$1" > "$src/libray.cmake" ||
        fail "$1: doc/EMBEDDING.md shows no block for it"
    case $1 in
    add_subdirectory)
        mkdir "$src/third_party"
        ln -s "$top" "$src/third_party/libray" ;;
    FetchContent)
        if git -C "$top" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
            $make --no-print-directory -s dist BUILD="$tmp/dist" \
                DIST_TARBALL="$src/libray-$VERSION.tar.gz" >/dev/null ||
                fail "make dist failed"
        else
            tar -C "$(dirname "$top")" --exclude="$(basename "$top")/build" \
                -czf "$src/libray-$VERSION.tar.gz" "$(basename "$top")"
        fi ;;
    esac
}

# consume MODE DIR ARGS...: configure and build the consumer.
consume() {
    mode=$1 dir=$2
    shift 2
    make_project "$mode" "$dir"
    # Not the outer make's jobserver: cmake runs its own make.
    env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL \
        cmake -S "$dir-src" -B "$dir" -DLIBRAY_SNIPPET="$dir-src/libray.cmake" \
        -DLIBRAY_USE="$mode" -DLIBRAY_SOURCE_DIR="$top" \
        -DCMAKE_C_COMPILER="$CC" -DCMAKE_C_FLAGS="$CFLAGS" \
        -DCMAKE_EXE_LINKER_FLAGS="$LDFLAGS" \
        -DCMAKE_SHARED_LINKER_FLAGS="$LDFLAGS" \
        -DCMAKE_EXPORT_COMPILE_COMMANDS=ON "$@" > "$dir.log" 2>&1 ||
        { cat "$dir.log" >&2; fail "$mode: cmake could not configure the consumer"; }
    env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL \
        cmake --build "$dir" --parallel "$jobs" >> "$dir.log" 2>&1 ||
        { cat "$dir.log" >&2; fail "$mode: cmake could not build the consumer"; }
}

# same_build MODE DIR PNG SRC: the sources and flags CMake used, libray's
# tree at SRC, are the Makefile's under that PNG setting.
same_build() {
    mode=$1 dir=$2 libsrc=$4
    expected_sources=$(make_sources "$3")
    list=$(find "$dir" -name libray-sources.txt | head -n 1)
    [ -n "$list" ] || fail "$mode: CMakeLists.txt wrote no libray-sources.txt"
    got=$(sort "$list")
    [ "$got" = "$expected_sources" ] || fail "$mode: CMake builds
$got
where the Makefile builds
$expected_sources"
    # One compile command a line: "file" then "command" in the JSON.
    awk -v top="$libsrc/" '
        /"command":/ { cmd = $0 }
        /"file":/ {
            f = $0; sub(/.*"file": *"/, "", f); sub(/".*/, "", f)
            if (index(f, top "src/") == 1)
                print substr(f, length(top) + 1) "\t" cmd
        }' "$dir/compile_commands.json" > "$tmp/commands"
    n=$(wc -l < "$tmp/commands")
    [ "$n" -eq "$(echo "$expected_sources" | wc -l)" ] ||
        fail "$mode: compile_commands.json has $n library files"
    while IFS="$(printf '\t')" read -r file cmd; do
        for flag in -std=c99 -ffp-contract=off -fno-fast-math \
                    -D_POSIX_C_SOURCE=200809L -fvisibility=hidden; do
            case " $cmd " in
            *" $flag "*) ;;
            *) fail "$mode: $file compiled without $flag: $cmd" ;;
            esac
        done
        case $file in
        src/query/intersect_avx2.c|src/scene/refit_avx2.c) copy=avx2 ;;
        *) copy=base ;;
        esac
        case "$copy:$AVX2_CFLAGS: $cmd " in
        avx2::*" -mavx2 "*)
            fail "$mode: $file compiled with -mavx2, which the Makefile does not give it here" ;;
        avx2::*) ;;
        avx2:*:*" $AVX2_CFLAGS "*) ;;
        avx2:*)
            fail "$mode: $file compiled without $AVX2_CFLAGS: $cmd" ;;
        *" -mavx2 "*) fail "$mode: $file compiled with -mavx2: $cmd" ;;
        esac
    done < "$tmp/commands"
}

# 1. add_subdirectory: static, PNG as the Makefile's.
if want add_subdirectory; then
    if [ "$png" = 1 ]; then png_opt=ON; else png_opt=OFF; fi
    consume add_subdirectory "$tmp/sub" -DLIBRAY_PNG="$png_opt" -DEXPECT_PNG="$png"
    same_build add_subdirectory "$tmp/sub" "$png" "$tmp/sub-src/third_party/libray"
    [ -f "$tmp/sub/third_party/libray/libray.a" ] ||
        fail "add_subdirectory: no static libray.a (BUILD_SHARED_LIBS unset)"
    "$tmp/sub/consumer" "$tmp/sub.png" >/dev/null
    if [ "$png" = 1 ]; then
        "$tmp/sub/whitted" "$tmp/cmake.png" 64 48 1 2 >/dev/null 2>&1 ||
            fail "add_subdirectory: whitted failed"
        cmp "$tmp/make.png" "$tmp/cmake.png" ||
            fail "add_subdirectory: whitted's picture differs from the Makefile's"
        echo "cmake-test: add_subdirectory: doc/EMBEDDING.md's block: libray::libray static, the Makefile's sources and flags; consumer ran; whitted.png byte-identical to the Makefile's"
    else
        echo "cmake-test: add_subdirectory: doc/EMBEDDING.md's block: libray::libray static without PNG, the Makefile's sources and flags; consumer ran (PNG=0: no picture to compare)"
    fi
fi

# 2. FetchContent from the tarball: shared, LIBRAY_PNG at its default.
if want FetchContent; then
    consume FetchContent "$tmp/fetch" -DBUILD_SHARED_LIBS=ON
    if pkg-config --exists libpng 2>/dev/null; then fetch_png=1 fetch_on=ON
    else fetch_png=0 fetch_on=OFF; fi
    grep -q "^-- libray: LIBRAY_PNG=$fetch_on: " "$tmp/fetch.log" ||
        fail "FetchContent: libpng $([ $fetch_png = 1 ] || echo not )found, yet configuring did not say LIBRAY_PNG=$fetch_on: $(grep 'libray:' "$tmp/fetch.log")"
    same_build FetchContent "$tmp/fetch" "$fetch_png" "$tmp/fetch/_deps/libray-src"
    so=$tmp/fetch/_deps/libray-build/libray.so.$VERSION
    [ -f "$so" ] || fail "FetchContent: no $so (BUILD_SHARED_LIBS=ON)"
    soname=$(objdump -p "$so" | awk '$1 == "SONAME" {print $2}')
    [ "$soname" = "libray.so.$SOMAJOR" ] ||
        fail "FetchContent: soname '$soname', not libray.so.$SOMAJOR"
    bad=$(nm -D --defined-only "$so" | awk '$2 != "A" {print $3}' | grep -v '^ray_' || true)
    [ -z "$bad" ] || fail "FetchContent: libray.so exports $bad"
    needs_png=0
    if objdump -p "$so" | grep NEEDED | grep -qi png; then needs_png=1; fi
    [ "$needs_png" = "$fetch_png" ] ||
        fail "FetchContent: LIBRAY_PNG=$fetch_on by default, yet libray.so $([ $needs_png = 1 ] || echo does not )need libpng"
    "$tmp/fetch/consumer" "$tmp/fetch.png" >/dev/null
    echo "cmake-test: FetchContent: doc/EMBEDDING.md's block with the make dist tarball: libray::libray shared ($soname, ray_* exported alone, LIBRAY_PNG=$fetch_on by default, said at configure time), the Makefile's sources; consumer ran"
fi
