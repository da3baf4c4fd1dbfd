#!/bin/sh
# SPDX-License-Identifier: MIT
# test-check-abi.sh DIR BASELINE SOMAJOR -- the ABI guard's self-test (make
# abi-test): scripts/check-abi.sh must pass a library with the recorded
# ABI and fail, with abidiff's report, on each kind of break.  The shared
# libraries are built here from the amalgamation in DIR (libray.c and
# ray.h, one compile at -O0 each: the ABI does not depend on the build,
# and the first case shows it equal to the Makefile's):
#
#   as is              passes;
#   a field reordered  in a scratch copy of ray.h, ray_camera's first two
#                      member lines swapped (its size unchanged, its
#                      members' offsets not): fails, naming the fields;
#   a field appended   to ray_camera: fails (a minor release may do it,
#                      recording it);
#   a function removed ray_version_string made local by the version
#                      script: fails;
#   a function added   one more ray_* function: fails (it needs its
#                      version node and a minor version, and the baseline
#                      recorded).
#
# CC and LDFLAGS come from the environment.  Skipped as check-abi.sh is
# (no abigail-tools).
set -eu
dir=$1 baseline=$2 somajor=$3
: "${CC:=cc}" "${LDFLAGS:=}"
top=$(pwd)

if ! command -v abidiff >/dev/null 2>&1; then
    echo "abi-test: no abidiff here: the guard's self-test skipped"
    exit 0
fi
tmp=$(mktemp -d "${TMPDIR:-/tmp}/libray-abi-test.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "abi-test self-test: $*" >&2; exit 1; }

# shared NAME MAP OBJECTS...: link tmp/NAME/libray.so.
shared() {
    name=$1 map=$2
    shift 2
    # shellcheck disable=SC2086 # LDFLAGS is a list
    $CC -shared -Wl,-soname,libray.so."$somajor" -Wl,--version-script="$map" \
        $LDFLAGS -o "$tmp/$name/libray.so" "$@" -lm -lpthread
}
# object NAME DIR: compile DIR/libray.c into tmp/NAME/libray.o.
object() {
    mkdir -p "$tmp/$1"
    $CC -std=c99 -O0 -g -fPIC -fvisibility=hidden -c "$2/libray.c" \
        -o "$tmp/$1/libray.o"
}

# expect_fail NAME HEADERS WHAT TEXT...: the guard fails on it, its report
# holding each TEXT.
expect_fail() {
    name=$1 headers=$2 what=$3
    shift 3
    if scripts/check-abi.sh compare "$tmp/$name/libray.so" "$headers" \
        "$baseline" > "$tmp/$name.out" 2>&1; then
        cat "$tmp/$name.out" >&2
        fail "the guard passed $what"
    fi
    for text in "$@"; do
        grep -qF -e "$text" "$tmp/$name.out" ||
            { cat "$tmp/$name.out" >&2; fail "$what: the report does not say '$text'"; }
    done
    # The report's line with the last TEXT, as evidence.
    echo "abi-test: the guard fails on $what: $(grep -m 1 -F -e "$text" "$tmp/$name.out" | sed 's/^ *//')"
}

# 1. As it is.
object pristine "$dir"
shared pristine "$top/src/libray.map" "$tmp/pristine/libray.o"
scripts/check-abi.sh compare "$tmp/pristine/libray.so" "$dir" "$baseline" \
    > "$tmp/pristine.out" 2>&1 ||
    { cat "$tmp/pristine.out" >&2; fail "the amalgamation's library, unchanged, fails the guard"; }

# 2. ray_camera's first two member lines swapped.
mkdir -p "$tmp/reordered/src"
cp "$dir/libray.c" "$tmp/reordered/src/"
awk '
    /^typedef struct ray_camera \{/ { print; inside = 1; n = 0; next }
    inside && n == 0 { first = $0; n = 1; next }
    inside && n == 1 { print; print first; inside = 0; swapped = 1; next }
    { print }
    END { if (!swapped) exit 1 }' "$dir/ray.h" > "$tmp/reordered/src/ray.h" ||
    fail "no 'typedef struct ray_camera {' in $dir/ray.h to reorder"
object reordered "$tmp/reordered/src"
shared reordered "$top/src/libray.map" "$tmp/reordered/libray.o"
expect_fail reordered "$tmp/reordered/src" "ray_camera's fields reordered" \
    "struct ray_camera" "offset changed"

# 3. A field appended to ray_camera (what a minor release may do, the
#    baseline recording it: doc/DESIGN.md).
mkdir -p "$tmp/appended/src"
cp "$dir/libray.c" "$tmp/appended/src/"
awk '
    /^typedef struct ray_camera \{/ { inside = 1 }
    inside && /^\} ray_camera;/ {
        print "    double abi_selftest_appended;"; inside = 0; added = 1 }
    { print }
    END { if (!added) exit 1 }' "$dir/ray.h" > "$tmp/appended/src/ray.h" ||
    fail "no '} ray_camera;' in $dir/ray.h to append to"
object appended "$tmp/appended/src"
shared appended "$top/src/libray.map" "$tmp/appended/libray.o"
expect_fail appended "$tmp/appended/src" "a field appended to ray_camera" \
    "struct ray_camera" "type size changed"

# 4. A function removed from the exports.
mkdir -p "$tmp/removed"
printf 'LIBRAY_%s {\n    global:\n        ray_*;\n    local:\n        ray_version_string;\n        *;\n};\n' "$somajor" \
    > "$tmp/removed.map"
shared removed "$tmp/removed.map" "$tmp/pristine/libray.o"
expect_fail removed "$dir" "ray_version_string removed" \
    "1 Removed function" "'function const char* ray_version_string()'"

# 5. A function added.
mkdir -p "$tmp/added"
printf '%s\n' 'int ray_abi_selftest_added(void);' \
    'int ray_abi_selftest_added(void) { return 1; }' > "$tmp/added/added.c"
$CC -std=c99 -O0 -g -fPIC -c "$tmp/added/added.c" -o "$tmp/added/added.o"
shared added "$top/src/libray.map" "$tmp/pristine/libray.o" \
    "$tmp/added/added.o"
expect_fail added "$dir" "a function added" \
    "1 Added function" "'function int ray_abi_selftest_added()'"
echo "abi-test: the guard's self-test passed (the amalgamation's library passes; a reordered struct, a grown struct, a removed and an added function fail)"
