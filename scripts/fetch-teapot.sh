#!/bin/sh
# SPDX-License-Identifier: MIT
# fetch-teapot.sh [DIR] -- the Utah teapot as Bezier patches, written to
# DIR/teapot.bpt (default data/, not committed) for examples/teapot.c:
#   teapot.bpt    32 bicubic patches over 290 control points
#
# The data is Martin Newell's teapot (1975) as Jim Blinn, Frank Crow and
# Eric Haines passed it on; it is not committed because the original
# data set has no clear licence.  It is taken from three.js
# (examples/jsm/geometries/TeapotGeometry.js, MIT licence), pinned to the
# npm package three@0.150.0: its "teapotPatches" (32 x 16 0-based indices)
# and "teapotVertices" (x, y, z triples).  Newell's original list has 306
# vertices; this one has 290, every one used: it leaves out 4 points near
# the lid's top that no patch names, and the bottom patches share the
# body's lowest ring of points instead of 12 copies of them.  The surface
# is the same.
#
# The output is the usual "Newell patch file" text (examples/bpt.h reads
# it): the number of patches; one line per patch of 16 comma-separated
# 1-based vertex indices (the patch's 4 rows of 4 control points); the
# number of vertices; one line "x, y, z" per vertex.  z is up.
# Uses npm if present, else curl on the npm registry; and awk.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${1:-$root/data}
mkdir -p "$dir"
cd "$dir"
if [ -f teapot.bpt ]; then
    exit 0
fi

version=0.150.0
member=package/examples/jsm/geometries/TeapotGeometry.js
# sha256 of $member in three@$version: the data we checked, byte for byte.
sha256=650c0b4224e4c4082b0877e6c4793d14f1f33e88c5151abeae7a1ba2cf518ad4

if [ ! -f three-TeapotGeometry.js ]; then
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    if command -v npm >/dev/null 2>&1; then
        (cd "$tmp" && npm pack "three@$version" --silent >/dev/null)
    elif command -v curl >/dev/null 2>&1; then
        curl -fsSL "https://registry.npmjs.org/three/-/three-$version.tgz" \
            -o "$tmp/three-$version.tgz"
    else
        echo "fetch-teapot: needs npm or curl (apt-get install -y curl)" >&2
        exit 1
    fi
    tar -xzf "$tmp/three-$version.tgz" -C "$tmp" "$member"
    cp "$tmp/$member" three-TeapotGeometry.js.tmp
    mv three-TeapotGeometry.js.tmp three-TeapotGeometry.js
fi

if command -v sha256sum >/dev/null 2>&1; then
    sum=$(sha256sum three-TeapotGeometry.js | cut -d' ' -f1)
elif command -v shasum >/dev/null 2>&1; then
    sum=$(shasum -a 256 three-TeapotGeometry.js | cut -d' ' -f1)
else
    sum=$sha256
    echo "fetch-teapot: no sha256sum or shasum: checksum not checked" >&2
fi
if [ "$sum" != "$sha256" ]; then
    echo "fetch-teapot: three-TeapotGeometry.js: unexpected sha256 $sum" >&2
    exit 1
fi

# The two arrays are JavaScript literals: numbers separated by commas over
# many lines, with /*rim*/-style comments, and "- 0.784" for -0.784.
# Removing comments and blanks leaves the bare fields.  Every field is
# checked before anything is written.
awk '
function fail(msg) {
    print "fetch-teapot: three-TeapotGeometry.js: " msg | "cat 1>&2"
    bad = 1
    exit 1
}
/const teapotPatches = \[/ { section = "patches"; next }
/const teapotVertices = \[/ { section = "vertices"; next }
section != "" && /^[ \t]*\];/ { section = ""; next }
section != "" {
    gsub(/\/\*[^*]*\*\//, "")
    gsub(/[ \t\r]/, "")
    n = split($0, field, ",")
    for (i = 1; i <= n; i++) {
        if (field[i] == "")
            continue
        if (section == "patches") {
            if (field[i] !~ /^[0-9]+$/)
                fail("bad patch index \"" field[i] "\"")
            index_of[index_count++] = field[i] + 0
        } else {
            if (field[i] !~ /^-?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$/)
                fail("bad coordinate \"" field[i] "\"")
            coord[coord_count++] = field[i]
        }
    }
}
END {
    if (bad)
        exit 1
    # 32 patches of 16 indices; 290 vertices of 3 coordinates.
    if (index_count != 32 * 16)
        fail(index_count " patch indices, expected 512")
    if (coord_count != 290 * 3)
        fail(coord_count " coordinates, expected 870")
    for (i = 0; i < index_count; i++)
        if (index_of[i] >= coord_count / 3)
            fail("patch index " index_of[i] " out of range")
    print index_count / 16
    for (i = 0; i < index_count; i += 16) {
        line = index_of[i] + 1
        for (k = 1; k < 16; k++)
            line = line ", " (index_of[i + k] + 1)
        print line
    }
    print coord_count / 3
    for (i = 0; i < coord_count; i += 3)
        print coord[i] ", " coord[i + 1] ", " coord[i + 2]
}' three-TeapotGeometry.js > teapot.bpt.tmp || {
    rm -f teapot.bpt.tmp
    exit 1
}
mv teapot.bpt.tmp teapot.bpt
patches=$(sed -n 1p teapot.bpt)
vertices=$(sed -n "$((patches + 2))p" teapot.bpt)
echo "fetch-teapot: $dir/teapot.bpt ($patches patches, $vertices vertices)" >&2
