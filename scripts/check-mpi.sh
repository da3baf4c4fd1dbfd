#!/bin/sh
# SPDX-License-Identifier: MIT
# check-mpi.sh BUILD -- examples/mpi_render (issue 20), run by make check
# where mpicc and mpirun exist:
#
#   * its command line keeps the examples' conventions (-h and --help exit 0, a
#     bad argument 2, before MPI starts);
#   * the picture is byte-identical (cmp) to the plain example's PNG of the
#     same scene and options, at 1, 2 and 3 ranks and several band sizes
#     (RAY_MPI_BAND), for whitted, cornell, a small OBJ, one Bezier patch
#     (the teapot's scene) and adaptive
#     antialiasing;
#   * a rank that fails its setup (RAY_MPI_FAIL_RANK, the test hook, or a
#     scene file that is not there) makes the run exit non-zero with
#     "rank N: why" on stderr, within a time limit (no hang), and leaves
#     no PNG; so does an output that cannot be written.
#
# Small pictures and --oversubscribe: the machine may have fewer cores
# than ranks.  OpenMPI refuses to run as root unless told it may.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-build}" && pwd)
exe=$build/mpi/mpi_render
LC_ALL=C
export LC_ALL
unset RAY_ADAPTIVE RAY_MPI_BAND RAY_MPI_FAIL_RANK 2>/dev/null || true
OMPI_ALLOW_RUN_AS_ROOT=1
OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_ALLOW_RUN_AS_ROOT OMPI_ALLOW_RUN_AS_ROOT_CONFIRM
# Under make sanitize: OpenMPI leaks at exit from plugins it has already
# unloaded (frames of "<unknown module>"), which no suppression can name,
# so leak checking is off for these runs; out-of-bounds accesses and
# undefined behaviour are still caught.
ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0
export ASAN_OPTIONS

tmp=$(mktemp -d "${TMPDIR:-/tmp}/check-mpi.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM
failures=0
checks=0
fail() {
    echo "check-mpi: $*" >&2
    failures=$((failures + 1))
}

# mpi NP ARGS...: mpi_render under mpirun with NP ranks, at most 120 s
# (a hang is a failure); sets $rc, output in $tmp/out and $tmp/err.
mpi() {
    np=$1
    shift
    rc=0
    checks=$((checks + 1))
    timeout 120 mpirun -np "$np" --oversubscribe "$exe" "$@" \
        > "$tmp/out" 2> "$tmp/err" || rc=$?
    [ "$rc" -ne 124 ] || fail "mpirun -np $np $*: timed out (a hang)"
}

# The conventions, without mpirun: the arguments are read before MPI.
for help in --help -h; do
    rc=0
    "$exe" "$help" > "$tmp/out" 2> "$tmp/err" || rc=$?
    checks=$((checks + 1))
    [ "$rc" -eq 0 ] || fail "mpi_render $help: exit $rc, expected 0"
    grep -q "^usage: mpi_render" "$tmp/out" || fail "$help: no usage on stdout"
done
for bad in "whitted x.png -5 3" "whitted x.png 12abc 3" \
           "whitted x.png 8 8 0" "--bogus"; do
    rc=0
    # shellcheck disable=SC2086
    "$exe" $bad > "$tmp/out" 2> "$tmp/err" || rc=$?
    checks=$((checks + 1))
    [ "$rc" -eq 2 ] || fail "mpi_render $bad: exit $rc, expected 2"
done
grep -q "^usage: mpi_render" "$tmp/err" || fail "--bogus: no usage on stderr"

. "$root/scripts/example-inputs.sh"
example_inputs "$tmp"

# same NAME REF NP BAND ARGS...: the NP-rank picture of ARGS (bands of
# BAND rows; "-": the default) is REF, byte for byte.
same() {
    name=$1 ref=$2 np=$3 band=$4
    shift 4
    rm -f "$tmp/mpi.png"
    if [ "$band" = - ]; then
        mpi "$np" "$@"
    else
        RAY_MPI_BAND=$band mpi "$np" "$@"
    fi
    if [ "$rc" -ne 0 ]; then
        fail "$name, $np ranks, band $band: exit $rc: $(head -c 300 "$tmp/err")"
    elif ! cmp -s "$ref" "$tmp/mpi.png"; then
        fail "$name, $np ranks, band $band: not the same bytes as the one-process PNG"
    fi
}

"$build/examples/whitted" "$tmp/whitted.png" 160 120 2 2 >/dev/null 2>&1
for np in 1 2 3; do
    for band in 1 7 -; do
        same whitted "$tmp/whitted.png" "$np" "$band" whitted "$tmp/mpi.png" 160 120 2 1
    done
done
"$build/examples/cornell" "$tmp/cornell.png" 96 96 4 2 >/dev/null 2>&1
same cornell "$tmp/cornell.png" 3 5 cornell "$tmp/mpi.png" 96 96 4 1
"$build/examples/mesh" "$tmp/tri.obj" "$tmp/mesh.png" 80 60 1 2 >/dev/null 2>&1
same mesh "$tmp/mesh.png" 2 3 "$tmp/tri.obj" "$tmp/mpi.png" 80 60 1 1
"$build/examples/teapot" "$tmp/patch.bpt" "$tmp/teapot.png" 64 48 1 2 >/dev/null 2>&1
same teapot "$tmp/teapot.png" 3 2 "$tmp/patch.bpt" "$tmp/mpi.png" 64 48 1 1
RAY_ADAPTIVE=0.05,2 "$build/examples/whitted" "$tmp/adaptive.png" 96 72 1 2 \
    >/dev/null 2>&1
RAY_ADAPTIVE=0.05,2 same adaptive "$tmp/adaptive.png" 3 4 whitted "$tmp/mpi.png" 96 72 1 1

# expect_failure WHAT TEXT: the last run failed, said TEXT, wrote nothing.
expect_failure() {
    [ "$rc" -ne 0 ] || fail "$1: exit 0, expected a failure"
    grep -qF -e "$2" "$tmp/err" ||
        fail "$1: no \"$2\" on stderr: $(head -c 300 "$tmp/err")"
    [ ! -e "$tmp/fail.png" ] || fail "$1: a PNG was written"
    rm -f "$tmp/fail.png"
}
for rank in 1 2 0; do
    RAY_MPI_FAIL_RANK=$rank mpi 3 whitted "$tmp/fail.png" 160 120 1 1
    expect_failure "RAY_MPI_FAIL_RANK=$rank" \
        "mpi_render: rank $rank: scene setup failed"
done
mpi 2 "$tmp/missing.obj" "$tmp/fail.png" 32 24 1 1
expect_failure "a missing scene file" "rank 0: cannot read scene $tmp/missing.obj"

# An output that cannot be written: refused by rank 0 before the render,
# every rank told, exit 1.
mpi 2 whitted "$tmp/no-such-dir/fail.png" 32 24 1 1
expect_failure "an unwritable output" "cannot write $tmp/no-such-dir/fail.png"

if [ "$failures" -ne 0 ]; then
    echo "check-mpi: $failures of $checks checks failed" >&2
    exit 1
fi
echo "check-mpi: $checks checks passed (byte-identical at 1-3 ranks, failures reported)"
