#!/bin/sh
# SPDX-License-Identifier: MIT
# check-install.sh MAKE BUILD PNG -- make install-test (part of make check):
#
#  1. make install into a staging directory (PREFIX=/opt/libray), the tree
#     then moved elsewhere: a program still compiles, links and runs
#     against the moved copy through pkg-config --define-prefix (libray.pc
#     names its paths relative to ${prefix}), and, when cmake is
#     installed, through find_package(libray) (tests/cmake-consumer: the
#     shared and the static target; librayConfig.cmake finds its paths from
#     its own location).  The programs check PNG output against PNG.
#  2. make install then make uninstall into an empty prefix leave it
#     empty; into a prefix that already has directories (some empty, one
#     with another package's file), those stay as they were.
#  3. What a user types (doc/BUILDING.md): make install into a prefix
#     outside the loader's path (no DESTDIR), then
#     cc app.c $(pkg-config --cflags --libs libray), nothing else: the
#     program RUNS (libray.pc's rpath; it used to exit 127, "libray.so.0:
#     cannot open shared object file"); install and uninstall ran ldconfig
#     exactly when it applies (root, DESTDIR empty: a stand-in LDCONFIG
#     records the calls), and libray.pc has no rpath for the loader's own
#     directories (PREFIX=/usr).  And doc/EMBEDDING.md's pkg-config lines,
#     as written: the --static one links libray.a (pkg_config_lines).
#
# CC, CFLAGS and LDFLAGS come from the environment (the Makefile's).
set -eu
make=$1 build=$2 png=$3
: "${CC:=cc}" "${CFLAGS:=}" "${LDFLAGS:=}"
top=$(pwd)

tmp=$(mktemp -d "${TMPDIR:-/tmp}/libray-install-test.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "install-test: $*" >&2; exit 1; }
mk() { $make --no-print-directory -s BUILD="$build" PNG="$png" "$@" >/dev/null; }

# pkg_config_lines PREFIX: doc/EMBEDDING.md's pkg-config lines, as
# written (scripts/doc-block.sh), each run in a directory of its own with
# app.c the consumer and PKG_CONFIG_PATH at PREFIX; cc is the build's
# compiler with its flags (a sanitizer's runtime must be linked too).
# The program a line without --static builds needs libray.so.MAJOR; the
# one with --static does not (readelf -d: no NEEDED entry for it), and
# both run.
pkg_config_lines() {
    n=0
    "$top/scripts/doc-block.sh" pkg-config > "$tmp/pc-lines" ||
        fail "doc/EMBEDDING.md shows no pkg-config lines"
    while IFS= read -r line; do
        n=$((n + 1))
        dir=$tmp/pc-line$n
        mkdir "$dir"
        cp "$top/tests/cmake-consumer/main.c" "$dir/app.c"
        # shellcheck disable=SC2016 # expanded by the sh that runs the line
        printf '%s\n' 'cc() { command $CC $CFLAGS "$@" $LDFLAGS; }' "$line" > "$dir/line.sh"
        (cd "$dir" && PKG_CONFIG_PATH="$1/lib/pkgconfig" CC="$CC" \
            CFLAGS="$CFLAGS" LDFLAGS="$LDFLAGS" sh -e line.sh) ||
            fail "doc/EMBEDDING.md's '$line' failed against PREFIX=$1"
        (cd "$dir" && env -u LD_LIBRARY_PATH ./a.out) ||
            fail "doc/EMBEDDING.md's '$line' built a program that fails"
        needs=$(readelf -d "$dir/a.out" | grep NEEDED | grep -c 'libray\.so' || true)
        case $line in
        *--static*) [ "$needs" -eq 0 ] ||
            fail "'$line' built a program that needs libray.so: $(readelf -d "$dir/a.out" | grep NEEDED)" ;;
        *) [ "$needs" -eq 1 ] ||
            fail "'$line' built a program that does not need libray.so" ;;
        esac
    done < "$tmp/pc-lines"
    [ "$n" -ge 2 ] || fail "doc/EMBEDDING.md shows $n pkg-config lines, not the shared and the --static one"
    echo "install-test: doc/EMBEDDING.md's $n pkg-config lines built and ran as written; --static's program needs no libray.so"
}

# 1. A moved install.
mk install DESTDIR="$tmp/stage" PREFIX=/opt/libray
mv "$tmp/stage/opt/libray" "$tmp/moved"
rm -rf "$tmp/stage"
moved=$tmp/moved
flags=$(PKG_CONFIG_PATH="$moved/lib/pkgconfig" pkg-config --define-prefix \
        --cflags --libs libray)
case "$flags" in
*"-I$moved/include"*"-L$moved/lib"*) ;;
*) fail "pkg-config --define-prefix gave '$flags', not the moved tree $moved" ;;
esac
static=$(PKG_CONFIG_PATH="$moved/lib/pkgconfig" pkg-config --define-prefix \
         --static --libs libray)
case "$png:$static" in
1:*-lpng*|0:*) ;;
*) fail "pkg-config --static --libs libray gave '$static': no libpng" ;;
esac
case "$png:$static" in
0:*png*) fail "PNG=0, yet pkg-config --static --libs libray gave '$static'" ;;
esac
# No -Wl,-rpath of our own: libray.pc's Libs carries it (PREFIX /opt).
# shellcheck disable=SC2086 # the flags are lists
$CC $CFLAGS -DEXPECT_PNG="$png" "$top/tests/cmake-consumer/main.c" \
    -o "$tmp/pc-consumer" $flags $LDFLAGS
ldd "$tmp/pc-consumer" | grep -q "$moved/lib/libray.so" ||
    fail "the pkg-config consumer does not load $moved/lib/libray.so"
"$tmp/pc-consumer" "$tmp/pc.png" ||
    fail "the pkg-config consumer, linked with libray.pc's flags alone, did not run"
echo "install-test: pkg-config --define-prefix: built and ran against a moved install, with libray.pc's flags alone"

if command -v cmake >/dev/null 2>&1; then
    # Not the outer make's jobserver: cmake runs its own make.
    env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL \
        cmake -S "$top/tests/cmake-consumer" -B "$tmp/cmake" \
        -DCMAKE_PREFIX_PATH="$moved" -DCMAKE_C_COMPILER="$CC" \
        -DCMAKE_C_FLAGS="$CFLAGS" -DCMAKE_EXE_LINKER_FLAGS="$LDFLAGS" \
        -DEXPECT_PNG="$png" > "$tmp/cmake.log" 2>&1 ||
        { cat "$tmp/cmake.log" >&2; fail "cmake could not configure the consumer"; }
    env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL \
        cmake --build "$tmp/cmake" > "$tmp/cmake.log" 2>&1 ||
        { cat "$tmp/cmake.log" >&2; fail "cmake could not build the consumer"; }
    ldd "$tmp/cmake/consumer" | grep -q "$moved/lib/libray.so" ||
        fail "the CMake consumer does not load $moved/lib/libray.so"
    "$tmp/cmake/consumer" "$tmp/cmake.png"
    "$tmp/cmake/consumer_static" "$tmp/cmake-static.png"
    echo "install-test: cmake find_package(libray): libray::libray and libray::libray_static built and ran against a moved install"
else
    echo "install-test: no cmake here: the CMake consumer is skipped (.ci/run installs cmake)"
fi

# 2. Uninstall into an empty prefix, and into one with directories.
mk install DESTDIR="$tmp/empty" PREFIX=/usr/local
mk uninstall DESTDIR="$tmp/empty" PREFIX=/usr/local
left=$(cd "$tmp/empty/usr/local" && find . -mindepth 1 | sort)
[ -z "$left" ] || fail "uninstall left in an empty prefix: $left"

kept=$tmp/kept/usr/local
mkdir -p "$kept/include" "$kept/lib/pkgconfig" "$kept/share/man/man3"
touch "$kept/lib/pkgconfig/other.pc"
before=$(cd "$kept" && find . | sort)
mk install DESTDIR="$tmp/kept" PREFIX=/usr/local
mk uninstall DESTDIR="$tmp/kept" PREFIX=/usr/local
after=$(cd "$kept" && find . | sort)
[ "$before" = "$after" ] ||
    fail "uninstall changed a prefix's own directories: before: $before; after: $after"
echo "install-test: uninstall leaves an empty prefix empty and another prefix's directories as they were"

# 3. A live install (DESTDIR empty) into a prefix the loader does not
# search, built as doc/BUILDING.md says and run with no LD_LIBRARY_PATH.
# The stand-in ldconfig appends a line per call: as root, install and
# uninstall call it once each; otherwise never (the rpath serves); and
# never with DESTDIR set (parts 1 and 2 used it: no log yet).
printf '%s\n' '#!/bin/sh' 'echo called >> "${0%/*}/ldconfig.log"' \
    > "$tmp/ldconfig"
chmod +x "$tmp/ldconfig"
live=$tmp/live
mk install PREFIX="$live" LDCONFIG="$tmp/ldconfig" DESTDIR="$tmp/staged"
[ ! -e "$tmp/ldconfig.log" ] ||
    fail "ldconfig ran for an install with DESTDIR set"
mk install PREFIX="$live" LDCONFIG="$tmp/ldconfig"
grep -q -- '^Libs:.*-Wl,-rpath,${libdir}' "$live/lib/pkgconfig/libray.pc" ||
    fail "libray.pc for PREFIX=$live has no rpath: $(grep '^Libs:' "$live/lib/pkgconfig/libray.pc")"
flags=$(PKG_CONFIG_PATH="$live/lib/pkgconfig" pkg-config --cflags --libs libray)
# shellcheck disable=SC2086 # the flags are lists
$CC $CFLAGS -DEXPECT_PNG="$png" "$top/tests/cmake-consumer/main.c" \
    -o "$tmp/live-consumer" $flags $LDFLAGS
rc=0
env -u LD_LIBRARY_PATH "$tmp/live-consumer" "$tmp/live.png" || rc=$?
[ "$rc" -eq 0 ] ||
    fail "cc app.c \$(pkg-config --cflags --libs libray) for PREFIX=$live built a program that exits $rc"
pkg_config_lines "$live"
mk uninstall PREFIX="$live" LDCONFIG="$tmp/ldconfig"
calls=0
[ ! -e "$tmp/ldconfig.log" ] || calls=$(wc -l < "$tmp/ldconfig.log")
if [ "$(id -u)" = 0 ]; then want=2; else want=0; fi
[ "$calls" -eq "$want" ] ||
    fail "ldconfig ran $calls times for install and uninstall as uid $(id -u), not $want"
mk libray.pc BUILD="$tmp/pc-usr" PREFIX=/usr
if grep -q -- '^Libs:.*-rpath' "$tmp/pc-usr/libray.pc"; then
    fail "libray.pc for PREFIX=/usr has an rpath: $(grep '^Libs:' "$tmp/pc-usr/libray.pc")"
fi
echo "install-test: cc app.c \$(pkg-config --cflags --libs libray) ran against PREFIX=$live (rpath from libray.pc; none for /usr); ldconfig ran $calls times as uid $(id -u), 0 with DESTDIR"
