#!/bin/sh
# SPDX-License-Identifier: MIT
# check-layers.sh -- no source file reaches above its layer (issue 15).
#
# The library's private headers are layers, each including only the one
# below it:  vec.h < prim.h < bvh.h < scene.h < trace.h < camera.h, with
# image.h beside prim.h on vec.h, watertight.h on prim.h and traverse.h
# (the queries, a source file built twice) on scene.h, packet.h (their
# eight-ray form, in the AVX2 copy) on traverse.h.  A file may
# include headers of its own layer or below, never above; the primitives
# (every .c file that is not listed as a higher layer below) stand on
# prim.h, so they cannot see the BVH, the scene or the trace context.
# Prints the include graph and fails naming any file that breaks this.
set -eu
cd "$(dirname "$0")/../src"

level() {
    case "$1" in
    ray.h) echo 0 ;;
    vec.h) echo 10 ;;
    image.h) echo 15 ;;
    prim.h) echo 20 ;;
    watertight.h) echo 25 ;;
    bvh.h) echo 30 ;;
    scene.h) echo 40 ;;
    traverse.h) echo 45 ;;
    packet.h) echo 46 ;;
    trace.h) echo 50 ;;
    camera.h) echo 60 ;;
    # The layer each source file belongs to (its highest allowed include).
    image.c|png.c|png_none.c) echo 15 ;;
    bvh.c) echo 30 ;;
    scene.c|mesh.c|surfaces.c|kinds.c|error.c|instance.c|dynamic.c|closest.c) echo 40 ;;
    intersect.c) echo 45 ;;
    intersect_avx2.c) echo 46 ;;
    trace.c|light.c|sampling.c|direct.c|photons.c) echo 50 ;;
    camera.c|render.c) echo 60 ;;
    *.c) echo 25 ;;                   # a primitive (or optics, spawn)
    *) echo 99 ;;                     # an unknown header: refused
    esac
}

bad=0
for f in *.c *.h; do
    own=$(level "$f")
    deps=$(sed -n 's/^#include "\([^"]*\)".*/\1/p' "$f" | tr '\n' ' ')
    echo "$f: $deps"
    for d in $deps; do
        dl=$(level "$d")
        # A header sits strictly above what it includes; a .c file may
        # include its own layer.
        case "$f" in
        *.h) [ "$dl" -lt "$own" ] || { echo "layers: $f includes $d (not below it)"; bad=1; } ;;
        *.c) [ "$dl" -le "$own" ] || { echo "layers: $f includes $d (above its layer)"; bad=1; } ;;
        esac
    done
done >&2
[ "$bad" -eq 0 ] && echo "layers-test: no file includes above its layer"
exit "$bad"
