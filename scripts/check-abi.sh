#!/bin/sh
# SPDX-License-Identifier: MIT
# check-abi.sh compare|record LIB HEADERS BASELINE -- the ABI guard (make
# abi-test, part of make check; make abi-baseline):
#
#   compare  LIB, a shared libray built with -g, against BASELINE (the
#            committed abi/libray.abi) with libabigail's abidiff: any
#            function removed, added or changed, any change of a public
#            type's layout (a field moved, resized or retyped, a struct
#            grown), or of the soname, prints abidiff's report and fails.
#   record   writes LIB's ABI to BASELINE with abidw, after printing what
#            changed against the old one.
#
# HEADERS is the directory of the ray.h LIB was compiled with: the types
# declared there are the public ones; the library's own (src/) are left
# out (--drop-private-types), so that an opaque struct's insides are free
# to change.  The baseline records the public functions and variables,
# the types they reach and where they are declared (file and line: a line
# that moved is not a change), the soname and the symbols' version nodes
# (src/libray.map), for one architecture: on another one the comparison is
# skipped, as it is without abigail-tools (.ci/run installs them) or for
# a library built without debug information (CFLAGS without -g).
set -eu
mode=$1 lib=$2 headers=$3 baseline=$4

for tool in abidw abidiff; do
    if ! command -v $tool >/dev/null 2>&1; then
        echo "abi-test: no $tool here: skipped (apt-get install abigail-tools; .ci/run installs it)"
        [ "$mode" = compare ] && exit 0
        exit 1
    fi
done
if ! objdump -h "$lib" | grep -q '\.debug_info'; then
    echo "abi-test: $lib has no debug information (CFLAGS without -g): skipped"
    [ "$mode" = compare ] && exit 0
    exit 1
fi

tmp=$(mktemp -d "${TMPDIR:-/tmp}/libray-abi.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

# The ABI as abidw writes it: file names without their directories, no
# build paths, no DT_NEEDED (libpng comes and goes with PNG=0), type ids
# as hashes, so that regenerating after a small change changes few lines.
abidw --headers-dir "$headers" --drop-private-types --no-corpus-path \
    --no-comp-dir-path --short-locs --no-elf-needed --type-id-style hash \
    --out-file "$tmp/now.abi" "$lib"

arch_of() { sed -n "s/^<abi-corpus[^>]* architecture='\([^']*\)'.*/\1/p" "$1" | head -n 1; }

case $mode in
compare)
    want=$(arch_of "$baseline") got=$(arch_of "$tmp/now.abi")
    if [ "$want" != "$got" ]; then
        echo "abi-test: $baseline was recorded for $want, this is $got: skipped"
        exit 0
    fi
    rc=0
    abidiff --hd2 "$headers" --drop-private-types "$baseline" "$lib" \
        > "$tmp/report" 2>&1 || rc=$?
    if [ "$rc" -ne 0 ]; then
        cat "$tmp/report"
        cat <<EOF
abi-test: the public ABI of $lib is not the one recorded in $baseline
(abidiff's report above; status $rc).  If the change is meant, record it
in the same commit: make abi-baseline, with doc/DESIGN.md's rules
("Versions and ABI"): functions only added: a new version node in
src/libray.map and the minor version up; anything removed or changed,
or a public struct's layout: the major version, hence the soname, up.
EOF
        exit 1
    fi
    echo "abi-test: $lib has the ABI recorded in $baseline ($(grep -c '<elf-symbol ' "$baseline") symbols)"
    ;;
record)
    if [ -f "$baseline" ]; then
        abidiff --hd2 "$headers" --drop-private-types "$baseline" "$lib" ||
            true
    fi
    # The licence line second (make license-test), inside the root
    # element: abidiff knows the file by its first bytes.
    {
        sed -n '1p' "$tmp/now.abi"
        echo "  <!-- SPDX-License-Identifier: MIT -->"
        echo "  <!-- libray's public ABI, written by make abi-baseline (scripts/check-abi.sh); make check compares the library with it -->"
        sed '1d' "$tmp/now.abi"
    } > "$baseline"
    echo "abi-baseline: $baseline written from $lib: commit it with the change, and see doc/DESIGN.md, \"Versions and ABI\", for the version and the soname"
    ;;
*)
    echo "check-abi.sh: unknown mode '$mode'" >&2
    exit 2
    ;;
esac
