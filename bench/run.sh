#!/bin/sh
# SPDX-License-Identifier: MIT
# run.sh BUILD_DIR -- run every benchmark, write bench/RESULTS.md, put the
# headline table of "What accuracy costs" into README.md (between the
# <!-- accuracy:begin --> and <!-- accuracy:end --> markers) and, when
# gnuplot is installed, draw bench/accuracy.png.  BENCH_QUICK=1 for a short
# run (under a minute).  Prints the results as it goes.
set -eu
build=${1:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
out=bench/RESULTS.md
plots=$(mktemp -d)
trap 'rm -rf "$plots"' EXIT

scripts/fetch-bunny.sh data >/dev/null 2>&1 || echo "bench: no bunny (npm or curl needed): mesh rows skipped" >&2
{
    echo "<!-- SPDX-License-Identifier: MIT -->"   # scripts/check-spdx.sh
    echo "# libray benchmark results"
    echo
    echo "Command: \`${BENCH_QUICK:+BENCH_QUICK=1 }make bench\`; machine: $(uname -m),"
    echo "$(nproc) CPUs ($(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //' || echo unknown)),"
    echo "$(${CC:-cc} --version | head -1); $(date -u +%Y-%m-%d)."
    echo
    "$build/bench/accuracy" data "$plots"
    "$build/bench/numerics"
    "$build/bench/selfhit"
    "$build/bench/effects" data
    "$build/bench/threads"
    "$build/bench/surfaces"
    "$build/bench/mesh" data
} | tee "$out.tmp"
mv "$out.tmp" "$out"

# Tables copied into the README between <!-- NAME:begin --> and
# <!-- NAME:end -->: the primitives (headline), the curved surfaces, the
# effects, the thread speed-up and the meshes.
splice() {
    awk -v f="$2" -v b="<!-- $1:begin -->" -v e="<!-- $1:end -->" '
        $0 == b { print; while ((getline l < f) > 0) print l; skip=1; next }
        $0 == e { skip=0 }
        !skip' README.md > "$plots/README.md" && cp "$plots/README.md" README.md
}
awk '/^### Primitives/{on=1} on&&/^### Images/{exit} on' "$out" > "$plots/headline.md"
splice accuracy "$plots/headline.md"
awk '/^\| surface \|/{on=1} on&&!/^\|/{exit} on' "$out" > "$plots/surfaces.md"
splice surfaces "$plots/surfaces.md"
awk '/^Pruned \(effect analysis/{on=1} /^## Whitted scene/{exit} on' "$out" |
    sed -e :a -e '/^\n*$/{$d;N;ba' -e '}' > "$plots/effects.md"
splice effects "$plots/effects.md"
awk '/^\| threads \|/{on=1} on&&!/^\|/{exit} on' "$out" > "$plots/threads.md"
splice threads "$plots/threads.md"
awk '/^Memory on a /{on=1} on' "$out" > "$plots/mesh.md"
splice mesh "$plots/mesh.md"

if command -v gnuplot >/dev/null 2>&1; then
    gnuplot <<GP
set terminal pngcairo size 800,500 noenhanced
set output "bench/accuracy.png"
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
    echo "bench: wrote bench/accuracy.png" >&2
else
    echo "bench: gnuplot not installed: no plot (apt-get install gnuplot-nox)" >&2
fi
echo "bench: wrote $out" >&2
