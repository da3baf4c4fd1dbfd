#!/bin/sh
# SPDX-License-Identifier: MIT
# mpi.sh BUILD_DIR -- one frame across MPI ranks on this machine
# (examples/mpi_render, issue 20): the render time of Whitted's scene at
# 1, 2 and 3 ranks, and the speed-up against 1 rank, printed as Markdown.
# bench/run.sh runs it when mpirun and BUILD/mpi/mpi_render exist.
#
# Two rows per rank count: one render thread per rank (the ranks are the
# only parallelism, so up to the machine's cores the speed-up is what the
# distribution delivers), and all CPUs per rank (the cores are shared out
# either way, so the ideal is 1.0x and what is below it is the cost of
# the bands, the messages and the oversubscription).  --bind-to none:
# OpenMPI binds each of up to 2 ranks to one core by default, which would
# crowd a rank's threads onto that core.  The time is the one
# rank 0 prints (setup, render and gather, not mpirun's start); the median
# of interleaved repetitions after a warm-up run, the rank counts
# alternating, as the other benchmarks do.  BENCH_QUICK=1: a smaller
# frame, one repetition.  BENCH_QUICK=smoke (make check's smoke run,
# bench/run.sh): a tiny frame, 1 and 2 ranks, one thread each, no
# warm-up: the script's every step, at two mpiruns' cost.
set -eu
build=${1:-build}
exe=$build/mpi/mpi_render
OMPI_ALLOW_RUN_AS_ROOT=1
OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_ALLOW_RUN_AS_ROOT OMPI_ALLOW_RUN_AS_ROOT_CONFIRM
# Under make sanitize (make check's bench-smoke-test): OpenMPI's leaks at
# exit, as scripts/check-mpi.sh says; the rest is still checked.
ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0
export ASAN_OPTIONS
nps="1 2 3" threads="1 0" warm=1
if [ "${BENCH_QUICK:-}" = smoke ]; then
    w=16 h=12 s=1 reps=1 nps="1 2" threads=1 warm=0
elif [ -n "${BENCH_QUICK:-}" ]; then
    w=320 h=240 s=4 reps=1
else
    w=640 h=480 s=16 reps=5
fi
tmp=$(mktemp -d "${TMPDIR:-/tmp}/bench-mpi.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM

# run NP THREADS: the seconds rank 0 reports.
run() {
    mpirun -np "$1" --oversubscribe --bind-to none "$exe" whitted "$tmp/out.png" \
        "$w" "$h" "$s" "$2" 2>/dev/null |
        sed -n 's/.* in \([0-9.]*\) s$/\1/p'
}
median() {
    sort -g | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'
}

[ "$warm" = 0 ] || run 1 0 >/dev/null     # warm-up
for rep in $(seq "$reps"); do
    for t in $threads; do
        for np in $nps; do
            run "$np" "$t" >> "$tmp/t$t-np$np"
        done
    done
done

echo "## MPI: one frame across ranks"
echo
echo "Whitted's scene, ${w}x${h}, $s samples per pixel, rendered by"
echo "\`mpirun -np N --oversubscribe --bind-to none mpi_render\` on this machine ($(nproc) CPUs);"
echo "default bands (height / (16 x ranks) rows); median of $reps interleaved runs."
echo
echo "| ranks | threads per rank | time (s) | speed-up vs 1 rank |"
echo "|---|---|---|---|"
for t in $threads; do
    base=$(median < "$tmp/t$t-np1")
    for np in $nps; do
        m=$(median < "$tmp/t$t-np$np")
        # mpirun's status is lost in run's pipeline: no time, a failure.
        if [ -z "$m" ] || [ -z "$base" ]; then
            echo "bench/mpi.sh: mpirun -np $np $exe printed no time: it failed" >&2
            exit 1
        fi
        awk -v np="$np" -v t="$t" -v m="$m" -v b="$base" 'BEGIN {
            printf "| %d | %s | %.3f | %.2fx |\n", np,
                   t == 0 ? "all CPUs" : t, m, b / m }'
    done
done
echo
