#!/bin/sh
# SPDX-License-Identifier: MIT
# windows-deps.sh DEPS -- what make windows-check needs (doc/PLATFORMS.md):
# the MinGW-w64 cross compiler and Wine (Debian packages, installed when
# missing and we are root), and Check, libpng and zlib built for Windows
# with it, from Debian's own source packages, into DEPS/include and
# DEPS/lib (static libraries).  Built once: DEPS/stamp names what is
# there, and a second run with the same versions does nothing.
#
# The sources come through apt with a private list (DEPS/apt: a deb-src
# entry for the main archive only, Debian's own signing key), so the
# machine's apt configuration is not touched and no security-archive
# version is ever asked for (those answer 404 on deb.debian.org for
# source).  apt checks every file against the signed index; dpkg-source
# applies Debian's patches.  The upstream versions are pinned below, and
# the Debian revision is the one bookworm's main archive has.
#   zlib:  its .c files compiled directly (no configure: what libpng
#          needs of it, the gz* file functions aside);
#   libpng: its .c files with the shipped pnglibconf.h.prebuilt (the
#          configuration libpng's own makefiles use), which is what
#          ./configure --host=x86_64-w64-mingw32 produces, in seconds;
#   Check: CMake with a toolchain file for MinGW; only libcheck.a and
#          its headers are kept.
set -eu
deps=${1:?usage: windows-deps.sh DEPS}
host=${WIN_HOST:-x86_64-w64-mingw32}
suite=${DEBIAN_SUITE:-bookworm}
CHECK_VERSION=0.15.2
LIBPNG_VERSION=1.6.39
ZLIB_VERSION=1.2.13
stamp="$host check-$CHECK_VERSION libpng-$LIBPNG_VERSION zlib-$ZLIB_VERSION"

# ---------------------------------------------------------- packages
need=""
command -v "$host-gcc" >/dev/null 2>&1 || need="$need gcc-mingw-w64-x86-64"
command -v wine >/dev/null 2>&1 || need="$need wine wine64"
command -v dpkg-source >/dev/null 2>&1 || need="$need dpkg-dev"
command -v cmake >/dev/null 2>&1 || need="$need cmake"
if [ -n "$need" ]; then
    if [ "$(id -u)" != 0 ]; then
        echo "windows-deps: missing Debian packages:$need; install them with: sudo apt-get install -y --no-install-recommends$need" >&2
        exit 1
    fi
    echo "windows-deps: installing$need"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq >/dev/null
    apt-get install -y -qq --no-install-recommends $need >/dev/null
fi

if [ -f "$deps/stamp" ] && [ "$(cat "$deps/stamp")" = "$stamp" ]; then
    echo "windows-deps: $stamp (cached in $deps)"
    exit 0
fi
rm -rf "$deps"
mkdir -p "$deps/include" "$deps/lib" "$deps/src" "$deps/obj/z" \
         "$deps/obj/png" "$deps/apt/lists/partial" \
         "$deps/apt/cache/archives/partial"
deps=$(cd "$deps" && pwd)

# ----------------------------------------------------------- sources
keyring=/usr/share/keyrings/debian-archive-keyring.gpg
echo "deb-src [signed-by=$keyring] http://deb.debian.org/debian $suite main" \
    > "$deps/apt/sources.list"
# apt_private TOOL ARGS: apt-get or apt-cache on the private list.
apt_private() {
    tool=$1
    shift
    "$tool" -q -o Dir::Etc::SourceList="$deps/apt/sources.list" \
        -o Dir::Etc::SourceParts=/nonexistent \
        -o Dir::State::Lists="$deps/apt/lists" \
        -o Dir::Cache="$deps/apt/cache" -o Debug::NoLocking=1 \
        -o APT::Sandbox::User=root "$@"
}
apt_private apt-get update >/dev/null
# The bookworm revision of each pinned upstream version.
revision() {
    apt_private apt-cache showsrc "$1" 2>/dev/null |
        awk -v up="$2" '$1 == "Version:" { v = $2; u = v; sub(/^[0-9]+:/, "", u);
                                           sub(/-[^-]*$/, "", u); sub(/\.dfsg$/, "", u);
                                           if (u == up) print v }' | head -n 1
}
cd "$deps/src"
for p in "check $CHECK_VERSION" "libpng1.6 $LIBPNG_VERSION" "zlib $ZLIB_VERSION"; do
    set -- $p
    v=$(revision "$1" "$2")
    if [ -z "$v" ]; then
        echo "windows-deps: $suite's main archive has no $1 $2 any more" >&2
        exit 1
    fi
    echo "windows-deps: $1=$v"
    apt_private apt-get source --download-only "$1=$v" >/dev/null 2>&1
    dsc=$(ls "$1"_*.dsc | head -n 1)
    dpkg-source -q -x "$dsc" "$1" >/dev/null 2>&1
done

# ------------------------------------------------------------ builds
CC="$host-gcc"
AR="$host-ar"
ZLIB_SRCS="adler32 compress crc32 deflate infback inffast inflate inftrees trees uncompr zutil"
PNG_SRCS="png pngerror pngget pngmem pngpread pngread pngrio pngrtran pngrutil pngset pngtrans pngwio pngwrite pngwtran pngwutil"
jobs=$(nproc 2>/dev/null || echo 2)
# compile DIR OBJDIR FLAGS NAMES: NAMES's .c files, "jobs" at a time.
compile() {
    dir=$1 out=$2 flags=$3
    shift 3
    n=0
    for f in "$@"; do
        $CC -O2 $flags -c "$dir/$f.c" -o "$out/$f.o" &
        n=$((n + 1))
        if [ $n -ge "$jobs" ]; then wait; n=0; fi
    done
    wait
    for f in "$@"; do [ -f "$out/$f.o" ] || { echo "windows-deps: $dir/$f.c failed" >&2; exit 1; }; done
}
compile "$deps/src/zlib" "$deps/obj/z" "" $ZLIB_SRCS
(cd "$deps/obj/z" && $AR rcs "$deps/lib/libz.a" *.o)
cp "$deps/src/zlib/zlib.h" "$deps/src/zlib/zconf.h" "$deps/include/"

cp "$deps/src/libpng1.6/scripts/pnglibconf.h.prebuilt" \
   "$deps/src/libpng1.6/pnglibconf.h"
compile "$deps/src/libpng1.6" "$deps/obj/png" "-I$deps/include" $PNG_SRCS
(cd "$deps/obj/png" && $AR rcs "$deps/lib/libpng.a" *.o)
(cd "$deps/src/libpng1.6" && cp png.h pngconf.h pnglibconf.h "$deps/include/")

cat > "$deps/mingw.cmake" <<EOF
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(CMAKE_C_COMPILER $host-gcc)
set(CMAKE_RC_COMPILER $host-windres)
set(CMAKE_FIND_ROOT_PATH /usr/$host)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
EOF
mkdir -p "$deps/obj/check"
# CMake takes CFLAGS and LDFLAGS from the environment, where make puts a
# command line's (CI's CFLAGS="-O2 -g -Werror", in MAKEFLAGS too): Check
# is built with its own flags, not held to libray's warnings (its check.c
# warns under gcc 12).
(unset CFLAGS CPPFLAGS LDFLAGS MAKEFLAGS MFLAGS &&
 cd "$deps/obj/check" &&
 cmake -DCMAKE_TOOLCHAIN_FILE="$deps/mingw.cmake" -DCMAKE_BUILD_TYPE=Release \
       -DCHECK_ENABLE_TESTS=OFF -DBUILD_TESTING=OFF \
       "$deps/src/check" >cmake.log 2>&1 &&
 make -j"$jobs" check >make.log 2>&1) || {
    echo "windows-deps: Check's build failed: $deps/obj/check/*.log" >&2
    exit 1
}
cp "$deps/obj/check/src/libcheck.a" "$deps/lib/"
cp "$deps/obj/check/check_stdint.h" "$deps/include/"
# libcheck.a formats its messages with MinGW's C99 printf (it calls
# __mingw_vsnprintf), so its assertions' formats are checked by those
# rules (gnu_printf), not msvcrt's (what "printf" means to MinGW's GCC,
# which would refuse the tests' %zu and %Lg).
sed 's/CK_ATTRIBUTE_FORMAT(printf,/CK_ATTRIBUTE_FORMAT(gnu_printf,/' \
    "$deps/obj/check/src/check.h" > "$deps/include/check.h"
nm_undef=$("$host-nm" -u "$deps/lib/libcheck.a" 2>/dev/null || true)
case "$nm_undef" in
*__mingw_vsnprintf*) ;;
*) echo "windows-deps: libcheck.a does not use MinGW's C99 printf" >&2; exit 1 ;;
esac
echo "$stamp" > "$deps/stamp"
echo "windows-deps: built $stamp into $deps"
