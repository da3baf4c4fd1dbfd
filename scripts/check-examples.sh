#!/bin/sh
# SPDX-License-Identifier: MIT
# check-examples.sh BUILD -- every example program in BUILD/examples keeps
# the examples' command-line conventions (examples/common.h, issue 18):
#
#   * -h and --help print the usage (on stdout) and exit 0;
#   * a bad argument exits 2 with a message naming the argument: width -5,
#     width 12abc, width 70000, samples 0, an unknown option, and for the
#     examples without sizes an argument too many;
#   * an output that cannot be written (in a directory that does not
#     exist; a directory) fails before the render, exit 1, with the file's
#     name and errno's text, printing no progress or statistics and
#     leaving no file behind;
#   * an input file that does not exist exits 1 naming it and errno's text;
#   * a small render with stderr in a file exits 0, writes the PNG, puts
#     no '\r' in that file (plain progress lines, not a redrawn bar), and
#     prints the scene's effects beside its ray statistics.
#
# The examples that read a file get a tiny one written here (mesh: a
# three-triangle OBJ, teapot: one Bezier patch) or doc/cornell.png
# (textures).  An example the list below does not know is run with no
# input, as the convention has it.  Prints each failure; fails if any.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-build}" && pwd)
LC_ALL=C                                 # errno's texts in English
export LC_ALL
unset RAY_ADAPTIVE || true

tmp=$(mktemp -d "${TMPDIR:-/tmp}/check-examples.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM
mkdir "$tmp/work"
cd "$tmp/work"                           # where default outputs would land

. "$root/scripts/example-inputs.sh"
example_inputs "$tmp"

checks=0
failures=0
fail() {
    echo "check-examples: $name: $*" >&2
    failures=$((failures + 1))
}

# run ARGS...: the example with its input first; sets $rc, output in
# $tmp/out and $tmp/err.
run() {
    rc=0
    "$exe" ${input:+"$input"} "$@" > "$tmp/out" 2> "$tmp/err" || rc=$?
    checks=$((checks + 1))
}

# expect STATUS WHAT TEXT...: the last run exited STATUS and its stderr
# (stdout for --help) holds each TEXT.
expect() {
    status=$1 what=$2
    shift 2
    [ "$rc" -eq "$status" ] || fail "$what: exit $rc, expected $status"
    for text in "$@"; do
        grep -qF -e "$text" "$tmp/out" "$tmp/err" ||
            fail "$what: no \"$text\" in its output: $(head -c 300 "$tmp/err")"
    done
}

# The work directory holds exactly the names given (nothing left behind).
expect_left() {
    what=$1
    shift
    # shellcheck disable=SC2012  # the names are this script's own
    left=$(ls -A "$tmp/work" | tr '\n' ' ')
    [ "$left" = "$*${*:+ }" ] || fail "$what: left behind: '$left'"
}

cr=$(printf '\r')
for exe in "$build"/examples/*; do
    if [ ! -f "$exe" ] || [ ! -x "$exe" ]; then continue; fi
    name=$(basename "$exe")
    case $name in
    mesh) input=$tmp/tri.obj ;;
    teapot) input=$tmp/patch.bpt ;;
    textures) input=$root/doc/cornell.png ;;
    *) input= ;;
    esac
    out=$tmp/work/out.png

    for help in --help -h; do
        run "$help"
        expect 0 "$help" "usage: $name"
        grep -q "usage: $name" "$tmp/out" || fail "$help: the usage not on stdout"
    done
    run --bogus
    expect 2 "--bogus" "unknown option '--bogus'" "usage: $name"

    # An example that writes no file (picking: queries only) takes no
    # arguments: one is refused, none runs.
    if grep -q "(no arguments)" "$tmp/err"; then
        run "$out"
        expect 2 "an argument" "usage: $name"
        run
        expect 0 "a run"
        expect_left "a run"
        continue
    fi
    # The usage (on stderr after --bogus) tells whether it takes sizes.
    if grep -q "width height" "$tmp/err"; then
        run "$out" -5 10
        expect 2 "width -5" "width" "'-5'" "usage: $name"
        run "$out" 12abc 10
        expect 2 "width 12abc" "width" "'12abc'"
        run "$out" 70000 10
        expect 2 "width 70000" "width" "'70000'"
        run "$out" 8 6 0
        expect 2 "samples 0" "samples" "'0'"
        sizes="16 12 1 2"
    else
        run "$out" 12
        expect 2 "an argument too many" "unexpected argument '12'"
        sizes=
    fi
    expect_left "bad arguments"

    run "$tmp/work/missing/out.png"
    expect 1 "output in a missing directory" \
        "$tmp/work/missing/out.png" "No such file or directory"
    if [ -s "$tmp/out" ] || grep -q '%' "$tmp/err"; then
        fail "output in a missing directory: rendered before failing"
    fi
    expect_left "output in a missing directory"
    mkdir "$tmp/work/dir"
    run "$tmp/work/dir"
    expect 1 "output a directory" "$tmp/work/dir" "Is a directory"
    if [ -s "$tmp/out" ] || grep -q '%' "$tmp/err"; then
        fail "output a directory: rendered before failing"
    fi
    expect_left "output a directory" dir
    rmdir "$tmp/work/dir"

    if [ -n "$input" ]; then
        real_input=$input input=$tmp/work/none.in
        run "$out"
        expect 1 "a missing input" "$input" "No such file or directory"
        input=$real_input
        expect_left "a missing input"
    fi

    # shellcheck disable=SC2086  # $sizes: several arguments or none
    run "$out" $sizes
    expect 0 "a small render"
    [ -s "$out" ] || fail "a small render: no $out"
    ! grep -q "$cr" "$tmp/err" || fail "a small render: '\\r' in stderr"
    if grep -q "rays primary" "$tmp/out"; then
        grep -q "effects the scene needs: [a-z]" "$tmp/out" ||
            fail "a small render: statistics without the scene's effects"
    fi
    if [ -n "$sizes" ]; then
        grep -q "^$name: 100% (12 of 12 rows)$" "$tmp/err" ||
            fail "a small render: no plain progress line for 100%"
    fi
    rm -f "$out"
    expect_left "a small render"
done

if [ "$failures" -gt 0 ]; then
    echo "check-examples: $failures of $checks runs failed" >&2
    exit 1
fi
echo "check-examples: $checks runs of the examples keep their conventions"
