#!/bin/sh
# SPDX-License-Identifier: MIT
# check-pages.sh -- the documentation stays what issue 29 made it (make
# check, pages-test):
#
#  1. README.md is a landing page of at most README_MAX_LINES (250)
#     lines: what libray is, the pictures, the two commands, two
#     examples, how to embed it, and links to doc/ for everything else.
#     A README that grows back fails here; the new text belongs in a
#     doc/ page.
#  2. No figure typed by hand: a measured figure in README.md or
#     doc/*.md stands between <!-- NAME:begin --> and <!-- NAME:end -->
#     markers, where bench/run.sh copies it from bench/RESULTS.md (and
#     bench-docs-test checks that it did), or it is not there.  Hand-typed
#     figures drifted (the README said 1.73x POV-Ray where the table said
#     1.30x).  What is caught is the shape of a measurement: a number with
#     a decimal point followed by a unit of time (ns, us, ms, s), a ratio
#     (x), a percentage, a rate (Mrays/s) or a size (bytes, KiB, MiB, GB,
#     ...), outside code blocks and the markers.  Whole numbers (sizes of
#     structures, settings, targets: "8-wide nodes of 256 bytes", "30 s a
#     target") are not taken for measurements.  A heuristic: it keeps the
#     usual slip out, not every one.
#
# Prints each offence as PAGE:LINE and fails.
set -eu
cd "$(dirname "$0")/.."
README_MAX_LINES=${README_MAX_LINES:-250}
bad=0

lines=$(wc -l < README.md)
if [ "$lines" -gt "$README_MAX_LINES" ]; then
    echo "pages-test: README.md has $lines lines, more than $README_MAX_LINES: move the detail to a doc/ page and link it" >&2
    bad=1
fi

for page in README.md doc/*.md; do
    awk -v page="$page" '
        /^```/ { code = !code; next }
        /^<!-- [A-Za-z0-9_-]+:begin -->$/ { spliced = 1; next }
        /^<!-- [A-Za-z0-9_-]+:end -->$/ { spliced = 0; next }
        code || spliced { next }
        {
            line = $0
            gsub(/`[^`]*`/, "", line)      # inline code: commands, names
            if (match(line, /[0-9]\.[0-9]+ ?(ns|µs|us|ms|s|seconds|x|×|%|Mrays\/s|bytes|KiB|MiB|GiB|kB|MB|GB)([^A-Za-z0-9]|$)/)) {
                printf "pages-test: %s:%d: a figure typed by hand, \"%s\": splice it from bench/RESULTS.md between markers (bench/run.sh) or leave it out\n", page, NR, substr(line, RSTART, RLENGTH) > "/dev/stderr"
                bad = 1
            }
        }
        END { exit bad }' "$page" || bad=1
done

[ "$bad" = 0 ] && echo "pages-test: README.md has $lines lines (at most $README_MAX_LINES); no figure typed by hand in README.md or doc/*.md outside the spliced tables"
exit "$bad"
