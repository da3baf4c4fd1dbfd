#!/bin/sh
# SPDX-License-Identifier: MIT
# check-version.sh MAKE BUILD -- make version-test (part of make check): the
# version is set in one place, include/ray.h's RAY_VERSION_MAJOR, _MINOR
# and _PATCH, and everything that states it agrees:
#
#   ray.h           RAY_VERSION_NUMBER and RAY_VERSION_STRING, as the
#                   compiler reads them, made of the three;
#   the library     ray_version_number() and ray_version_string() of
#                   BUILD/libray.a;
#   the Makefile    VERSION and SOMAJOR (make print-version); the shared
#                   library BUILD/libray.so.VERSION, soname libray.so.MAJOR;
#   libray.pc       its Version (make libray.pc, written here);
#   CMake           the installed package's librayConfig.cmake and
#                   librayConfigVersion.cmake (make cmake-config, here),
#                   and CMakeLists.txt's project version (the same
#                   cmake/libray-version.cmake, run as a script);
#   amalgamation    BUILD/amalgamation/libray.c's first lines;
#   CHANGELOG.md    its first section is this version's release
#                   ("## VERSION (YYYY-MM-DD)"), or "## Unreleased" above
#                   a newest release no newer than this version;
#   man pages       none carries a version (.Os is left to the system).
#
# CC, CFLAGS, LDFLAGS and LIBS come from the environment (the Makefile's).
set -eu
make=$1 build=$2
: "${CC:=cc}" "${CFLAGS:=}" "${LDFLAGS:=}" "${LIBS:=-lm -lpthread}"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/libray-version-test.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "version-test: $*" >&2; exit 1; }
checked=""

# 1. ray.h and the library, through the compiler.
cat > "$tmp/version.c" <<'EOF'
#include <stdio.h>
#include "ray.h"
int main(void)
{
    printf("%d %d %d %ld %s %d %s\n", RAY_VERSION_MAJOR, RAY_VERSION_MINOR,
           RAY_VERSION_PATCH, (long)RAY_VERSION_NUMBER, RAY_VERSION_STRING,
           ray_version_number(), ray_version_string());
    return 0;
}
EOF
# shellcheck disable=SC2086 # the flags are lists
$CC -std=c99 -Iinclude $CFLAGS $LDFLAGS -o "$tmp/version" "$tmp/version.c" \
    "$build/libray.a" $LIBS || fail "cannot build the version probe"
# shellcheck disable=SC2046 # the probe's words
set -- $("$tmp/version")
major=$1 minor=$2 patch=$3
version=$major.$minor.$patch
[ "$4" = $((major * 10000 + minor * 100 + patch)) ] ||
    fail "RAY_VERSION_NUMBER is $4, not major*10000 + minor*100 + patch of $version"
[ "$5" = "$version" ] || fail "RAY_VERSION_STRING is \"$5\", RAY_VERSION_* $version"
[ "$6" = "$4" ] && [ "$7" = "$version" ] ||
    fail "the library says $6 $7, ray.h $4 $version"
checked="ray.h, ray_version_*()"

# 2. The Makefile, the shared library.
# shellcheck disable=SC2046
set -- $($make --no-print-directory -s print-version)
[ "$1" = "$version" ] && [ "$2" = "$major" ] ||
    fail "the Makefile's VERSION $1, SOMAJOR $2; ray.h: $version"
so=$build/libray.so.$version
[ -f "$so" ] || fail "no $so"
soname=$(objdump -p "$so" | awk '$1 == "SONAME" {print $2}')
[ "$soname" = "libray.so.$major" ] || fail "$so: soname $soname, not libray.so.$major"
checked="$checked, the Makefile, $soname"

# 3. libray.pc and the CMake package, written here.
$make --no-print-directory -s BUILD="$tmp/out" libray.pc cmake-config >/dev/null
grep -qx "Version: $version" "$tmp/out/libray.pc" ||
    fail "libray.pc: $(grep '^Version' "$tmp/out/libray.pc")"
grep -q "^set(PACKAGE_VERSION \"$version\")" \
    "$tmp/out/cmake/librayConfigVersion.cmake" ||
    fail "librayConfigVersion.cmake does not set PACKAGE_VERSION $version"
grep -q "^set(libray_VERSION $version)" "$tmp/out/cmake/librayConfig.cmake" &&
    grep -q "libray\.so\.$version\"" "$tmp/out/cmake/librayConfig.cmake" &&
    grep -q "\"libray\.so\.$major\"" "$tmp/out/cmake/librayConfig.cmake" ||
    fail "librayConfig.cmake does not name version $version and soname libray.so.$major"
checked="$checked, libray.pc, the CMake package"
if command -v cmake >/dev/null 2>&1; then
    got=$(cmake -DRAY_H=include/ray.h -P cmake/libray-version.cmake 2>&1)
    [ "$got" = "libray-version: $version" ] ||
        fail "CMakeLists.txt's version: '$got'"
    checked="$checked, CMakeLists.txt"
fi

# 4. The amalgamation.
head -n 5 "$build/amalgamation/libray.c" | grep -q "libray $version " ||
    fail "$build/amalgamation/libray.c does not say libray $version"
checked="$checked, the amalgamation"

# 5. CHANGELOG.md.
first=$(grep -m 1 '^## ' CHANGELOG.md)
case $first in
"## $version ("[0-9][0-9][0-9][0-9]-[0-9][0-9]-[0-9][0-9]")") ;;
"## Unreleased"*)
    newest=$(grep '^## [0-9]' CHANGELOG.md | head -n 1 | sed 's/^## \([^ ]*\).*/\1/')
    if [ -n "$newest" ] &&
       [ "$(printf '%s\n%s\n' "$newest" "$version" | sort -t. -k1,1n -k2,2n -k3,3n | tail -n 1)" != "$version" ]; then
        fail "CHANGELOG.md's newest release $newest is newer than $version"
    fi ;;
*) fail "CHANGELOG.md's first section '$first' is neither '## $version (YYYY-MM-DD)' nor '## Unreleased'" ;;
esac
checked="$checked, CHANGELOG.md"

# 6. The man pages carry none.
if grep -n '^\.Os .*[0-9]' man/man3/*.3 man/man7/*.7; then
    fail "a man page names a version in .Os (above): leave .Os empty"
fi
echo "version-test: $version everywhere: $checked"
