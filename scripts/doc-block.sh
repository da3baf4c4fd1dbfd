#!/bin/sh
# SPDX-License-Identifier: MIT
# doc-block.sh NAME [PAGE] -- print the code block that PAGE
# (doc/EMBEDDING.md by default) marks with "<!-- embed: NAME -->" on the
# line before its opening fence, without the fences; fail, naming it, if
# there is none or it is empty.  make check's embedding tests
# (check-install.sh, check-cmake.sh, check-amalgamation.sh) run what the
# page shows through it, as written, so that the page cannot drift from
# what is tested.
set -eu
name=$1
page=${2:-$(dirname "$0")/../doc/EMBEDDING.md}
out=$(awk -v mark="<!-- embed: $name -->" '
    inside && /^```/ { exit }
    inside { print; next }
    marked && /^```/ { inside = 1; next }
    { marked = ($0 == mark) }' "$page")
if [ -z "$out" ]; then
    echo "doc-block.sh: $page has no block marked <!-- embed: $name -->" >&2
    exit 1
fi
printf '%s\n' "$out"
