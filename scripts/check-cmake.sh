#!/bin/sh
# SPDX-License-Identifier: MIT
# check-cmake.sh MAKE BUILD PNG -- make cmake-test (part of make check): libray
# as a CMake subproject (CMakeLists.txt) builds what the Makefile builds.
#
# tests/cmake-consumer, a project using libray as a game would, is
# configured and built twice with CMake:
#
#   add_subdirectory  libray::libray static (CMake's default), LIBRAY_PNG
#                     as the Makefile's PNG; its examples/whitted.c renders
#                     the picture make check renders, and the two files are
#                     compared with cmp;
#   FetchContent      from this source tree as a local path, with
#                     BUILD_SHARED_LIBS: libray.so.VERSION with the soname
#                     libray.so.MAJOR, exporting ray_* alone; LIBRAY_PNG
#                     left at a subproject's default (off), so the consumer
#                     expects RAY_ENOTSUP from ray_write_png.
#
# Each time the consumer runs (it renders a sphere and checks the linked
# library's version against the header's), and the library CMake built is
# held to the Makefile's: the same source files (make print-srcs, the
# Makefile's SRCS for that PNG setting, against libray-sources.txt, which
# CMakeLists.txt writes), and in
# compile_commands.json every library file compiled with -std=c99,
# -ffp-contract=off, -fno-fast-math, -D_POSIX_C_SOURCE=200809L and
# -fvisibility=hidden, and src/query/intersect_avx2.c alone with the
# Makefile's AVX2 flag (AVX2_CFLAGS, empty off x86).
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

# The Makefile's picture, rendered here at the size make check uses.
"$build/examples/whitted" "$tmp/make.png" 64 48 1 2 >/dev/null 2>&1 ||
    [ "$png" = 0 ] || fail "$build/examples/whitted failed"

# The Makefile's sources under PNG=$1, one a line.
make_sources() {
    $make --no-print-directory -s print-srcs PNG="$1" | tr ' ' '\n' |
        sed '/^$/d' | sort
}

# consume MODE DIR ARGS...: configure and build the consumer.
consume() {
    mode=$1 dir=$2
    shift 2
    # Not the outer make's jobserver: cmake runs its own make.
    env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL \
        cmake -S "$top/tests/cmake-consumer" -B "$dir" \
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

# same_build MODE DIR PNG: the sources and flags CMake used are the
# Makefile's under that PNG setting.
same_build() {
    mode=$1 dir=$2
    expected_sources=$(make_sources "$3")
    list=$(find "$dir" -name libray-sources.txt | head -n 1)
    [ -n "$list" ] || fail "$mode: CMakeLists.txt wrote no libray-sources.txt"
    got=$(sort "$list")
    [ "$got" = "$expected_sources" ] || fail "$mode: CMake builds
$got
where the Makefile builds
$expected_sources"
    # One compile command a line: "file" then "command" in the JSON.
    awk -v top="$top/" '
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
        case "$file:$AVX2_CFLAGS: $cmd " in
        src/query/intersect_avx2.c::*" -mavx2 "*)
            fail "$mode: $file compiled with -mavx2, which the Makefile does not give it here" ;;
        src/query/intersect_avx2.c::*) ;;
        src/query/intersect_avx2.c:*:*" $AVX2_CFLAGS "*) ;;
        src/query/intersect_avx2.c:*)
            fail "$mode: $file compiled without $AVX2_CFLAGS: $cmd" ;;
        *" -mavx2 "*) fail "$mode: $file compiled with -mavx2: $cmd" ;;
        esac
    done < "$tmp/commands"
}

# 1. add_subdirectory: static, PNG as the Makefile's.
if [ "$png" = 1 ]; then png_opt=ON; else png_opt=OFF; fi
consume add_subdirectory "$tmp/sub" -DLIBRAY_PNG="$png_opt" -DEXPECT_PNG="$png"
same_build add_subdirectory "$tmp/sub" "$png"
[ -f "$tmp/sub/libray/libray.a" ] ||
    fail "add_subdirectory: no static libray.a (BUILD_SHARED_LIBS unset)"
"$tmp/sub/consumer" "$tmp/sub.png" >/dev/null
if [ "$png" = 1 ]; then
    "$tmp/sub/whitted" "$tmp/cmake.png" 64 48 1 2 >/dev/null 2>&1 ||
        fail "add_subdirectory: whitted failed"
    cmp "$tmp/make.png" "$tmp/cmake.png" ||
        fail "add_subdirectory: whitted's picture differs from the Makefile's"
    echo "cmake-test: add_subdirectory: libray::libray static, the Makefile's sources and flags; consumer ran; whitted.png byte-identical to the Makefile's"
else
    echo "cmake-test: add_subdirectory: libray::libray static without PNG, the Makefile's sources and flags; consumer ran (PNG=0: no picture to compare)"
fi

# 2. FetchContent from a local path: shared, a subproject's default PNG.
consume FetchContent "$tmp/fetch" -DBUILD_SHARED_LIBS=ON -DEXPECT_PNG=0
same_build FetchContent "$tmp/fetch" 0
so=$tmp/fetch/_deps/libray-build/libray.so.$VERSION
[ -f "$so" ] || fail "FetchContent: no $so (BUILD_SHARED_LIBS=ON)"
soname=$(objdump -p "$so" | awk '$1 == "SONAME" {print $2}')
[ "$soname" = "libray.so.$SOMAJOR" ] ||
    fail "FetchContent: soname '$soname', not libray.so.$SOMAJOR"
bad=$(nm -D --defined-only "$so" | awk '$2 != "A" {print $3}' | grep -v '^ray_' || true)
[ -z "$bad" ] || fail "FetchContent: libray.so exports $bad"
if objdump -p "$so" | grep NEEDED | grep -qi png; then
    fail "FetchContent: LIBRAY_PNG's default under a parent project is off, yet libray.so needs libpng"
fi
"$tmp/fetch/consumer" "$tmp/fetch.png" >/dev/null
echo "cmake-test: FetchContent: libray::libray shared ($soname, ray_* exported alone, no libpng by default), the Makefile's sources; consumer ran"
