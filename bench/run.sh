#!/bin/sh
# SPDX-License-Identifier: MIT
# run.sh [--splice | --check] BUILD_DIR -- run every benchmark, write
# bench/RESULTS.md, copy its tables into the pages that show them
# (between the <!-- NAME:begin --> and <!-- NAME:end --> markers: doc/
# BENCHMARKS.md and doc/NUMERICS.md) and draw bench/accuracy.png with
# gnuplot (make bench installs it).  Prints the results as it goes.
#
# --splice: run nothing; copy the tables of the bench/RESULTS.md there
# is into the pages (after editing a page's prose around its markers).
# --check: run nothing; fail if a page's tables differ from what
# --splice would write (make check, bench-docs-test: every figure
# between markers is the last full run's, none typed by hand).
#
# BENCH_QUICK=1: a short run (under a minute) whose figures are not those
# of the documentation: it writes bench/RESULTS-quick.md and
# bench/accuracy-quick.png (both ignored by git) and copies nothing into
# doc/, so the last full run's figures stay where they are.
#
# BENCH_QUICK=smoke: make check's smoke test (make bench-smoke-mini):
# every program and every mode of the quick run, once, at the smallest
# sizes (a few rays, pixels and photons, one repetition: bench/bench.h's
# BENCH_SMOKE), a few CPU seconds in all, so that none breaks unseen.
# The meshes are a small closed sphere written here in place of the
# bunny's three files (nothing fetched, the same run with or without
# data/); the figures mean nothing, and go to BUILD_DIR/bench/
# RESULTS-smoke.md and its -smoke plots only, never bench/ or doc/.
#
# A benchmark that fails (exit status not 0) fails the run, named.
set -eu
mode=run
case ${1:-} in
--splice) mode=splice; shift ;;
--check) mode=check; shift ;;
esac
build=${1:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
smoke=0 kind=1
if [ "${BENCH_QUICK:-}" = smoke ] && [ "$mode" = run ]; then
    smoke=1 kind=smoke
fi
data=data
if [ "$smoke" = 1 ]; then
    out=$build/bench/RESULTS-smoke.md
    plot=$build/bench/accuracy-smoke.png
    cplot=$build/bench/caustics-smoke.png
elif [ -n "${BENCH_QUICK:-}" ] && [ "$mode" = run ]; then
    out=bench/RESULTS-quick.md
    plot=bench/accuracy-quick.png
    cplot=bench/caustics-quick.png
else
    out=bench/RESULTS.md
    plot=bench/accuracy.png
    cplot=bench/caustics.png
fi
plots=$(mktemp -d)
trap 'rm -rf "$plots"' EXIT

# sphere_obj SEGMENTS RINGS: a closed UV sphere, outward-facing, of
# 2 x SEGMENTS x (RINGS - 1) triangles, as Wavefront OBJ: the smoke
# run's stand-in for the bunny.
sphere_obj() {
    awk -v s="$1" -v r="$2" 'BEGIN {
        pi = atan2(0, -1)
        print "# bench/run.sh smoke mesh: a UV sphere"
        print "v 0 0 1"
        for (i = 1; i < r; i++)
            for (j = 0; j < s; j++)
                printf "v %.6f %.6f %.6f\n", sin(pi * i / r) * cos(2 * pi * j / s),
                    sin(pi * i / r) * sin(2 * pi * j / s), cos(pi * i / r)
        print "v 0 0 -1"
        for (j = 0; j < s; j++)
            print "f", 1, 2 + j, 2 + (j + 1) % s
        for (i = 1; i < r - 1; i++)
            for (j = 0; j < s; j++) {
                a = 2 + (i - 1) * s + j; b = 2 + (i - 1) * s + (j + 1) % s
                print "f", a, a + s, b + s
                print "f", a, b + s, b
            }
        for (j = 0; j < s; j++)
            print "f", 2 + (r - 2) * s + j, 2 + (r - 1) * s, 2 + (r - 2) * s + (j + 1) % s
    }'
}

# b PROGRAM ARGS: one benchmark; its failure stops the run, named (the
# list runs in a pipeline into tee, whose status alone sh would see).
b() {
    "$@" || { rc=$?; echo "bench: $* failed (exit status $rc)" >&2; exit 1; }
}

if [ "$mode" = run ]; then
    if [ "$smoke" = 1 ]; then
        data=$plots/data
        mkdir -p "$data" "$build/bench"
        sphere_obj 16 8 > "$data/bunny.obj"
        cp "$data/bunny.obj" "$data/bunny-2.obj"
        cp "$data/bunny.obj" "$data/bunny-4.obj"
    else
        scripts/fetch-bunny.sh data >/dev/null 2>&1 || echo "bench: no bunny (npm or curl needed): mesh rows skipped" >&2
    fi
    {
        echo "<!-- SPDX-License-Identifier: MIT -->"   # scripts/check-spdx.sh
        echo "# libray benchmark results"
        echo
        echo "Command: \`${BENCH_QUICK:+BENCH_QUICK=$kind }make bench\`; machine: $(uname -m),"
        echo "$(nproc) CPUs ($(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //' || echo unknown)),"
        echo "$(${CC:-cc} --version | head -1); $(date -u +%Y-%m-%d)."
        echo
        b "$build/bench/accuracy" "$data" "$plots"
        b "$build/bench/numerics"
        b "$build/bench/selfhit"
        b "$build/bench/effects" "$data"
        b "$build/bench/threads"
        b "$build/bench/cones"      # after threads: the effects splice ends at its "## Whitted scene"
        b "$build/bench/surfaces"
        b "$build/bench/mesh" "$data"
        b "$build/bench/raycost" "$data"
        # The same rays' work per ray, from the counted build (make
        # bench-counts), where it was built.
        if [ -x "$build/counts/bench/raycost" ]; then
            b env RAYCOST_TOOLS=0 "$build/counts/bench/raycost" "$data"
        fi
        b "$build/bench/contains" "$data"
        b "$build/bench/filter" "$data"
        b "$build/bench/packets" "$data"
        b "$build/bench/game" "$data"
        b "$build/bench/shapes" "$data"
        b "$build/bench/whitted" bench/whitted.pov
        b "$build/bench/caustics" "$plots"
        # MPI (issue 20): only where OpenMPI is installed and mpi_render built.
        if command -v mpirun >/dev/null 2>&1 && [ -x "$build/mpi/mpi_render" ]; then
            b bench/mpi.sh "$build"
        else
            echo "bench: no mpirun or $build/mpi/mpi_render: MPI rows skipped" >&2
        fi
        echo ok > "$plots/ran"
    } | tee "$out.tmp"
    [ -f "$plots/ran" ] || {
        rm -f "$out.tmp"
        echo "bench: a benchmark failed: $out not written" >&2
        exit 1; }
    mv "$out.tmp" "$out"
fi

# Tables copied into the pages between <!-- NAME:begin --> and
# <!-- NAME:end -->: into doc/BENCHMARKS.md the primitives (headline),
# the curved surfaces, the effects, the ray cones, the thread speed-up,
# the meshes, the live scenes, containment and distance grids against
# CGAL and OpenVDB, the shape queries and the Whitted scene against
# POV-Ray;
# into doc/NUMERICS.md the hard cases and the self-hits.  A marker
# missing from its page is an error, not a table silently dropped.
# splice PAGE NAME FILE: the copy goes to $plots/pages/PAGE, which
# --check compares with PAGE and the other modes copy over it.
mkdir -p "$plots/pages/doc"
splice() {
    page=$1
    [ -f "$plots/pages/$page" ] || cp "$page" "$plots/pages/$page"
    grep -qx "<!-- $2:begin -->" "$page" && grep -qx "<!-- $2:end -->" "$page" || {
        echo "bench: no <!-- $2:begin/end --> markers in $page" >&2; exit 1; }
    awk -v f="$3" -v b="<!-- $2:begin -->" -v e="<!-- $2:end -->" '
        $0 == b { print; while ((getline l < f) > 0) print l; skip=1; next }
        $0 == e { skip=0 }
        !skip' "$plots/pages/$page" > "$plots/page.md" &&
        cp "$plots/page.md" "$plots/pages/$page"
}
if [ -z "${BENCH_QUICK:-}" ] || [ "$mode" != run ]; then
    doc=doc/BENCHMARKS.md
    awk '/^### Primitives/{on=1} on&&/^### Images/{exit} on' "$out" > "$plots/headline.md"
    splice "$doc" accuracy "$plots/headline.md"
    awk '/^\| surface \|/{on=1} on&&!/^\|/{exit} on' "$out" > "$plots/surfaces.md"
    splice "$doc" surfaces "$plots/surfaces.md"
    awk '/^Pruned \(effect analysis/{on=1} /^## Whitted scene/{exit} on' "$out" |
        sed -e :a -e '/^\n*$/{$d;N;ba' -e '}' > "$plots/effects.md"
    splice "$doc" effects "$plots/effects.md"
    awk '/^## Ray cones/{on=1; next} on&&/^## /{exit} on' "$out" |
        sed -e '/./,$!d' -e :a -e '/^\n*$/{$d;N;ba' -e '}' > "$plots/cones.md"
    splice "$doc" cones "$plots/cones.md"
    awk '/^\| threads \|/{on=1} on&&!/^\|/{exit} on' "$out" > "$plots/threads.md"
    splice "$doc" threads "$plots/threads.md"
    awk '/^## What exactness costs/{exit} /^## What a query costs/{exit} /^## Inside or outside/{exit} /^## Packets:/{exit} /^## Games and tools/{exit} /^Memory on a /{on=1} on' "$out" > "$plots/mesh.md"
    splice "$doc" mesh "$plots/mesh.md"
    awk '/^## Packets:/{exit} /^## What exactness costs/{on=1; next} on' "$out" |
        sed -e '/./,$!d' > "$plots/filter.md"
    splice "$doc" filter "$plots/filter.md"
    awk '/^## Games and tools/{exit} /^## Packets:/{on=1; next} on' "$out" > "$plots/packets.md"
    splice "$doc" packets "$plots/packets.md"
    awk '/^## Shape queries/{exit} /^## Whitted scene against POV-Ray/{exit} /^## Games and tools/{on=1; next} on' "$out" > "$plots/game.md"
    splice "$doc" game "$plots/game.md"
    awk '/^## Inside or outside: ray_contains/{on=1; next} on&&/^## /{exit} on' "$out" |
        sed -e '/./,$!d' -e :a -e '/^\n*$/{$d;N;ba' -e '}' > "$plots/contains.md"
    splice "$doc" contains "$plots/contains.md"
    awk '/^## Whitted scene against POV-Ray/{exit} /^## Shape queries/{on=1; next} on' "$out" |
        sed -e '/./,$!d' > "$plots/shapes.md"
    splice "$doc" shapes "$plots/shapes.md"
    awk '/^## MPI: one frame/{exit} /^## Caustics: error/{exit} /^## Whitted scene against POV-Ray/{on=1; next} on' "$out" > "$plots/whitted.md"
    splice "$doc" whitted "$plots/whitted.md"
    awk '/^## MPI: one frame/{exit} /^## Caustics: error/{on=1; next} on' "$out" |
        sed -e '/./,$!d' > "$plots/caustics.md"
    splice "$doc" caustics "$plots/caustics.md"
    if grep -q '^## MPI: one frame' "$out"; then
        awk '/^## MPI: one frame/{on=1; next} on' "$out" |
            sed -e '/./,$!d' > "$plots/mpi.md"
        splice "$doc" mpi "$plots/mpi.md"
    fi
    awk '/^## Hard cases: naive against robust/{on=1; next} on&&/^### Self-hits/{exit} on' "$out" |
        sed -e '/./,$!d' -e :a -e '/^\n*$/{$d;N;ba' -e '}' > "$plots/numerics.md"
    splice doc/NUMERICS.md numerics "$plots/numerics.md"
    awk '/^### Self-hits per primitive kind/{on=1; next} on&&/^## /{exit} on' "$out" |
        sed -e '/./,$!d' -e :a -e '/^\n*$/{$d;N;ba' -e '}' > "$plots/selfhit.md"
    splice doc/NUMERICS.md selfhit "$plots/selfhit.md"
    # make windows-check WINDOWS_RECORD=1 writes bench/RESULTS-windows.md.
    if [ -f bench/RESULTS-windows.md ]; then
        awk '/^## libm:/{on=1; next} on' bench/RESULTS-windows.md |
            sed -e '/./,$!d' > "$plots/libm.md"
        splice doc/PLATFORMS.md libm "$plots/libm.md"
    fi
    stale=0
    for page in doc/BENCHMARKS.md doc/NUMERICS.md doc/PLATFORMS.md; do
        [ -f "$plots/pages/$page" ] || continue
        if [ "$mode" = check ]; then
            if ! cmp -s "$plots/pages/$page" "$page"; then
                echo "bench-docs-test: $page: its tables are not those of $out:" >&2
                diff "$page" "$plots/pages/$page" | head -20 >&2
                stale=1
            fi
        else
            cp "$plots/pages/$page" "$page"
        fi
    done
    if [ "$mode" = check ]; then
        [ "$stale" = 0 ] || {
            echo "bench-docs-test: the pages' tables are edited by hand or stale: bench/run.sh --splice copies $out's" >&2
            exit 1; }
        echo "bench-docs-test: every table between markers in doc/BENCHMARKS.md, doc/NUMERICS.md and doc/PLATFORMS.md is $out's (bench/RESULTS-windows.md's in PLATFORMS.md)"
        exit 0
    fi
    echo "bench: copied the tables into doc/BENCHMARKS.md and doc/NUMERICS.md" >&2
    [ "$mode" = run ] || exit 0
else
    echo "bench: BENCH_QUICK=$kind run: doc/*.md and bench/RESULTS.md left as they were" >&2
fi

if command -v gnuplot >/dev/null 2>&1; then
    gnuplot <<GP
set terminal pngcairo size 800,500 noenhanced
set output "$plot"
set title "Render time against image error (RMSE from a converged reference)"
set xlabel "render time (s), 2 threads"
set ylabel "RMSE"
set logscale xy
set key bottom left box opaque
set grid
plot "$plots/whitted-uniform.dat" with linespoints title "Whitted, uniform 1-64 spp", \
     "$plots/whitted-adaptive.dat" with linespoints title "Whitted, adaptive", \
     "$plots/cornell-uniform.dat" with linespoints title "Cornell, uniform", \
     "$plots/cornell-adaptive.dat" with linespoints title "Cornell, adaptive", \
     "$plots/bunny-uniform.dat" with linespoints title "bunny, uniform", \
     "$plots/bunny-adaptive.dat" with linespoints title "bunny, adaptive"
GP
    echo "bench: wrote $plot" >&2
    gnuplot <<GP
set terminal pngcairo size 800,500 noenhanced
set output "$cplot"
set title "Caustics: error against the photon pass and gather time"
set xlabel "caustics' time (s): render with photons minus without, 2 threads"
set ylabel "RMSE of the caustic image"
set logscale xy
set key top right box opaque
set grid
plot "$plots/caustics.dat" using 1:2 with linespoints title "10k to 1M photons, automatic radius", \
     "$plots/caustics.dat" using 1:2:(sprintf("%.0f", \$3)) with labels offset 0,1 notitle
GP
    echo "bench: wrote $cplot" >&2
else
    # make bench installs it (scripts/deps.sh gnuplot); run.sh run alone
    # may find none.
    echo "bench: gnuplot not installed: no plot (apt-get install gnuplot-nox)" >&2
fi
echo "bench: wrote $out" >&2
