#!/bin/sh
# SPDX-License-Identifier: MIT
# check-layers.sh [OBJDIR [OBJECT...]] -- the library's layers are its
# folders, and nothing reaches above its own (issue 26).
#
# A file's layer is the folder it lives in, src/LAYER/.  The layers, each
# with the layers below it that it may use (doc/DESIGN.md draws them):
#
#   core    vectors, rounding, errors, defaults, sampling, the platform
#   prim    one file per primitive and its bare test          -> core
#   image   images, mip maps, PNG                             -> core
#   accel   the BVH: build, wide nodes, refit                 -> core
#   scene   the store, meshes, kinds, changes, instances      -> core prim accel
#   query   traversal, packets, instances, all hits, closest  -> core prim accel scene
#   trace   the ray tree, lights, materials, photons          -> ... query image
#   render  camera, rows, progress                            -> ... trace
#
# Five checks, each printing every offence it finds:
#   0. rooms: every source file lives in a layer's folder and has at
#      most MAX_LINES lines (800: a file is one concept, split by concept
#      when it grows; include/ray.h, the one public header, is not here);
#   1. includes: a file includes headers of its own layer or of a layer
#      it may use ("ray.h" is everyone's), never one above or beside it;
#   2. calls: every symbol an object of OBJDIR/LAYER/ references that
#      another object of the library defines is defined in its own layer
#      or one it may use (nm; a static inline helper of a header is
#      copied into each object, so only real calls count);
#   3. circles: the objects' call graph has no loop at all, within a
#      layer too (tsort), so that every object can be read, and tested,
#      knowing only those below it;
#   4. the platform: outside src/core/platform*, a file includes only ISO
#      C's headers and the compiler's intrinsics (emmintrin.h,
#      immintrin.h, intrin.h), and libpng's <png.h> in src/image/png.c
#      alone -- no <pthread.h>, <unistd.h>, <sys/...>, <windows.h>: what
#      the library asks of the operating system is in one place, with a
#      POSIX and a Win32 branch (doc/PLATFORMS.md, issue 28).
# OBJDIR defaults to build/obj; the objects are OBJDIR/LAYER/NAME.o, those
# given (the Makefile names the library's) or else all there.  The
# sources are those of the tree the script is in, unless SRCDIR is set
# in the environment (the self-test's scratch trees).  Prints what it checked;
# exits 1 on any offence.  scripts/test-check-layers.sh proves it fails
# on each kind of offence, the circle that issue 26 opened among them.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
obj=${1:-$root/build/obj}
[ $# -gt 0 ] && shift
src=${SRCDIR:-$root/src}

LAYERS="core prim image accel scene query trace render"
MAX_LINES=${MAX_LINES:-800}

# The layers that layer $1 may use besides itself, in $below ("?" for a
# folder that is no layer).  A variable, not output: may_use runs once an
# include and once a call, and a $(...) is a process each time.
layer_below() {
    case "$1" in
    core) below="" ;;
    prim|image|accel) below="core" ;;
    scene) below="core prim accel" ;;
    query) below="core prim accel scene" ;;
    trace) below="core prim image accel scene query" ;;
    render) below="core prim image accel scene query trace" ;;
    *) below="?" ;;
    esac
}
uses() {
    layer_below "$1"
    echo "$below"
}

# 0 if layer $1 may use layer $2.
may_use() {
    [ "$1" = "$2" ] && return 0
    layer_below "$1"
    case " $below " in *" $2 "*) return 0 ;; esac
    return 1
}

bad=0
offence() {
    echo "layers: $*" >&2
    bad=1
}

# ------------------------------------------------------------ the files
for f in "$src"/*; do
    case "$(basename "$f")" in
    libray.map) ;;
    *) [ -d "$f" ] || offence "src/$(basename "$f") is in no layer" ;;
    esac
done
for d in "$src"/*/; do
    d=$(basename "$d")
    [ "$(uses "$d")" != "?" ] || offence "src/$d/ is not a layer ($LAYERS)"
done
tmp=$(mktemp -d "${TMPDIR:-/tmp}/check-layers.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM
# The sources by their names under src/ (LAYER/FILE), read by one wc and
# one awk for each kind of include, not by processes a file: the
# self-test runs this script a dozen times, and those processes were most
# of its time (issue 38).
rels=$(cd "$src" && for f in */*.c */*.h; do
           if [ -f "$f" ]; then echo "$f"; fi
       done)
# includes KIND: "LAYER/FILE NAME" for each #include "NAME" (KIND ")
# or #include <NAME> (KIND >) of the sources, in their order.
includes() {
    [ -n "$rels" ] || return 0
    # shellcheck disable=SC2086 # the names hold no space
    (cd "$src" && awk -v q="$1" '
        BEGIN { open = q == ">" ? "<" : "\""
                re = "^[[:space:]]*#[[:space:]]*include[[:space:]]*" open \
                     "[^" q "]*" q }
        match($0, re) {
            s = substr($0, 1, RLENGTH)
            sub(/^[^"<]*["<]/, "", s)
            s = substr(s, 1, length(s) - 1)
            n = split(s, w, /[ \t]+/)
            for (i = 1; i <= n; i++) if (w[i] != "") print FILENAME, w[i]
        }' $rels)
}
biggest=0
if [ -n "$rels" ]; then
    # shellcheck disable=SC2086 # the names hold no space
    (cd "$src" && wc -l $rels) > "$tmp/lines"
    while read -r n f; do
        [ "$f" != total ] || continue     # wc's sum, after two files or more
        [ "$n" -le "$MAX_LINES" ] ||
            offence "$f has $n lines, more than $MAX_LINES: split it by concept"
        [ "$n" -le "$biggest" ] || biggest=$n
    done < "$tmp/lines"
fi

# --------------------------------------------------------- 1. includes
n_inc=0
includes '"' > "$tmp/includes"
while read -r rel dep; do
    layer=${rel%%/*}
    n_inc=$((n_inc + 1))
    case "$dep" in
    ray.h) continue ;;
    */*) to=${dep%%/*} ;;
    *) offence "$rel includes \"$dep\": name its layer (\"$layer/$dep\")"
       continue ;;
    esac
    [ -f "$src/$dep" ] || { offence "$rel includes \"$dep\", which is not in src/"; continue; }
    may_use "$layer" "$to" ||
        offence "$rel includes \"$dep\": $to is not below $layer"
done < "$tmp/includes"

# ------------------------------------------------ 4. system headers
# ISO C99's headers, and the compilers' intrinsics (not the OS's).
ISO_HEADERS="assert.h complex.h ctype.h errno.h fenv.h float.h inttypes.h
iso646.h limits.h locale.h math.h setjmp.h signal.h stdarg.h stdbool.h
stddef.h stdint.h stdio.h stdlib.h string.h tgmath.h time.h wchar.h
wctype.h emmintrin.h immintrin.h intrin.h"
# shellcheck disable=SC2086,SC2116 # the list on one line, between spaces
iso_headers=" $(echo $ISO_HEADERS) "
n_sys=0
includes '>' > "$tmp/system"
while read -r rel h; do
    case "$rel" in core/platform*) continue ;; esac
    n_sys=$((n_sys + 1))
    case "$iso_headers" in *" $h "*) continue ;; esac
    [ "$h" = png.h ] && [ "$rel" = image/png.c ] && continue
    offence "$rel includes <$h>: a platform header outside src/core/platform* (platform.h asks the system)"
done < "$tmp/system"

# ------------------------------------------------------------ 2. calls
if [ $# -gt 0 ]; then
    objs=$(for o in "$@"; do echo "${o#"$obj"/}"; done | sort)
else
    objs=$(cd "$obj" && ls ./*/*.o 2>/dev/null | sed 's|^\./||' | sort)
fi
if [ -z "$objs" ]; then
    echo "layers: no objects in $obj/*/ (build the library first)" >&2
    exit 1
fi
for o in $objs; do
    [ -f "$obj/$o" ] || { echo "layers: no object $obj/$o" >&2; exit 1; }
done
# symbol object (every global definition) and object symbol (every use)
# One nm over all the objects for each list, -A putting its object's path
# at the head of every line: two nm processes an object were most of
# make check's layers-test and its self-test (142 for the library, about
# 20 CPU seconds a run; issue 38).
paths=$(for o in $objs; do echo "$obj/$o"; done)
# The object's name below OBJDIR, from nm -A's "PATH:ADDRESS" or "PATH:".
object_of='function object_of(f) {
    sub(/:[0-9A-Fa-f]*$/, "", f); return substr(f, length(pre) + 1) }'
# shellcheck disable=SC2086 # one path a word, as $objs
nm -A -g --defined-only $paths |
    awk -v pre="$obj/" "$object_of"' NF == 3 {print $3, object_of($1)}' |
    sort > "$tmp/defs"
# shellcheck disable=SC2086
nm -A -u $paths | awk -v pre="$obj/" "$object_of"' {print $NF, object_of($1)}' |
    sort > "$tmp/uses"
# caller callee symbol, for the uses the library itself defines
join "$tmp/uses" "$tmp/defs" | awk '$2 != $3 {print $2, $3, $1}' \
    | sort -u > "$tmp/calls"
n_calls=$(wc -l < "$tmp/calls")
while read -r from to sym; do
    lf=${from%%/*}
    lt=${to%%/*}
    may_use "$lf" "$lt" ||
        offence "$from calls $sym, defined in $to: $lt is not below $lf"
done < "$tmp/calls"

# ---------------------------------------------------------- 3. circles
# tsort names the objects of a loop on stderr and still exits 0 on some
# systems: its messages are the verdict.
awk '{print $1, $2}' "$tmp/calls" | sort -u > "$tmp/edges"
tsort "$tmp/edges" > /dev/null 2> "$tmp/loops" || true
if [ -s "$tmp/loops" ]; then
    offence "the objects call each other round a circle:"
    sed 's/^/    /' "$tmp/loops" >&2
fi

if [ "$bad" -ne 0 ]; then
    echo "layers-test: FAILED (doc/DESIGN.md: which layer may use which)" >&2
    exit 1
fi
echo "layers-test: $(echo "$objs" | wc -l | tr -d ' ') objects in 8 layers" \
     "($LAYERS): $n_inc includes and $n_calls calls between objects, none" \
     "above its layer, no circle; no file over $MAX_LINES lines (the" \
     "longest: $biggest); $n_sys system includes, no platform header" \
     "outside src/core/platform*"
