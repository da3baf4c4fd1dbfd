#!/bin/sh
# SPDX-License-Identifier: MIT
# against.sh REV [PAIRS] -- the tracer's scenes now against commit REV:
# the Cornell box (examples/cornell, 400x400, 4 samples per pixel), the
# bunny scene (examples/mesh data/bunny.obj, 480x360, 4 samples) and
# Whitted's scene (examples/whitted, 1024x768, 1 sample: bench/whitted's
# render against POV-Ray), one thread, each render timed by the example itself (its "N s" line,
# ray_render alone).  REV is built in a temporary worktree; the two
# binaries then run one after the other PAIRS times (default 5), so
# that the machine's load falls on both alike, and each pair gives a
# ratio, REV's time over ours: the median is printed, with whether the
# two pictures are the same bytes.  Issue 35's "1.5x faster than the
# round's start": bench/against.sh 99bc182 7.  Needs git, and data/
# bunny.obj (scripts/fetch-bunny.sh).
set -eu
rev=${1:?usage: against.sh REV [PAIRS]}
pairs=${2:-5}
root=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/against.XXXXXX")
cleanup() {
    git -C "$root" worktree remove --force "$tmp/old" 2>/dev/null || true
    rm -rf "$tmp"
}
trap cleanup EXIT INT TERM
git -C "$root" worktree add --detach "$tmp/old" "$rev" >/dev/null 2>&1
echo "against.sh: building $rev and the working tree"
make -C "$tmp/old" examples >/dev/null
make -C "$root" examples >/dev/null
cd "$root"

# seconds BINARY ARGS...: the render time the example prints.
seconds() {
    "$@" 2>&1 | sed -n 's/^[a-z]*: \([0-9.]*\) s, .*/\1/p'
}

# compare NAME INPUT ARGS...: PAIRS interleaved runs of example NAME
# (with its input file first, if INPUT is not empty), the median ratio.
compare() {
    name=$1 input=$2
    shift 2
    : > "$tmp/ratios"
    i=0
    while [ "$i" -lt "$pairs" ]; do
        a=$(seconds "$tmp/old/build/examples/$name" ${input:+"$input"} "$tmp/old.png" "$@")
        b=$(seconds "build/examples/$name" ${input:+"$input"} "$tmp/new.png" "$@")
        echo "$a $b" | awk '{ printf "%.4f\n", $1 / $2 }' >> "$tmp/ratios"
        printf '%s: %s s against %s s\n' "$name" "$a" "$b"
        i=$((i + 1))
    done
    median=$(sort -n "$tmp/ratios" | awk '{ r[NR] = $1 }
        END { print (NR % 2) ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2 }')
    same="the same picture"
    cmp -s "$tmp/old.png" "$tmp/new.png" || same="pictures that differ"
    printf '%s: %s / now = %.2fx (median of %s pairs), %s\n' \
        "$name" "$rev" "$median" "$pairs" "$same"
}

[ -f data/bunny.obj ] || { echo "against.sh: no data/bunny.obj" >&2; exit 1; }
compare cornell "" 400 400 4 1
compare mesh data/bunny.obj 480 360 4 1
compare whitted "" 1024 768 1 1
