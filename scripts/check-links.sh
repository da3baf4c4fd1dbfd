#!/bin/sh
# SPDX-License-Identifier: MIT
# check-links.sh -- every relative link of the Markdown documents
# (README.md, doc/*.md, CONTRIBUTING.md, CHANGELOG.md when present) names
# a file or directory that exists, and a "#anchor", in the same page or
# another, names one of that page's headings as GitHub spells it
# (lower case, punctuation other than "-" and "_" dropped, spaces as
# "-").  Links in fenced code blocks and absolute URLs are not checked.
# Prints each broken link as FILE: TARGET and fails.
set -eu
cd "$(dirname "$0")/.."

# The anchors of a Markdown file's headings, one a line.
anchors() {
    awk '/^```/ { code = !code; next }
         !code && /^#+ / {
             h = $0; sub(/^#+ +/, "", h); h = tolower(h)
             gsub(/[^a-z0-9 _-]/, "", h); gsub(/ /, "-", h); print h
         }' "$1"
}

# The relative link targets of a Markdown file, outside code blocks.
links() {
    awk '/^```/ { code = !code; next }
         !code {
             line = $0
             while (match(line, /\]\([^)]*\)/)) {
                 print substr(line, RSTART + 2, RLENGTH - 3)
                 line = substr(line, RSTART + RLENGTH)
             }
         }' "$1" | grep -Ev '^(https?|mailto):' || true
}

bad=0
for page in README.md doc/*.md CONTRIBUTING.md CHANGELOG.md; do
    [ -f "$page" ] || continue
    dir=$(dirname "$page")
    for target in $(links "$page"); do
        path=${target%%#*}
        anchor=
        case $target in *#*) anchor=${target#*#} ;; esac
        if [ -z "$path" ]; then
            file=$page
        else
            file=$dir/$path
        fi
        if [ ! -e "$file" ]; then
            echo "links-test: $page: $target: no such file" >&2
            bad=1
        elif [ -n "$anchor" ] && ! anchors "$file" | grep -qx -- "$anchor"; then
            echo "links-test: $page: $target: no such heading" >&2
            bad=1
        fi
    done
done
[ "$bad" = 0 ] && echo "links-test: every relative link of the Markdown pages resolves"
exit "$bad"
