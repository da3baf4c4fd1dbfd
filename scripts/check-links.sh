#!/bin/sh
# SPDX-License-Identifier: MIT
# check-links.sh -- every relative link of the Markdown documents
# (README.md, doc/*.md, CONTRIBUTING.md, CHANGELOG.md when present) names
# a file or directory that exists, and a "#anchor", in the same page or
# another, names one of that page's headings as GitHub spells it
# (lower case, punctuation other than "-" and "_" dropped, spaces as
# "-").  Links in fenced code blocks and absolute URLs are not checked.
# Prints each broken link as FILE: TARGET and fails.
#
# The anchors are checked last, all in one awk, which reads each page
# they point into once: an awk and a grep a link took 2 of make check's
# CPU seconds (issue 38).
set -eu
cd "$(dirname "$0")/.."
asked=$(mktemp)
trap 'rm -f "$asked"' EXIT

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
        elif [ -n "$anchor" ]; then
            printf '%s\t%s\t%s\t%s\n' "$page" "$target" "$file" "$anchor" >> "$asked"
        fi
    done
done
# PAGE TARGET FILE ANCHOR a line: FILE's headings as GitHub spells them,
# outside fenced code blocks, must hold ANCHOR.
awk -F '\t' '
    function headings(f,    line, code, h) {
        code = 0
        while ((getline line < f) > 0) {
            if (line ~ /^```/) { code = !code; continue }
            if (!code && line ~ /^#+ /) {
                h = line; sub(/^#+ +/, "", h); h = tolower(h)
                gsub(/[^a-z0-9 _-]/, "", h); gsub(/ /, "-", h)
                has[f SUBSEP h] = 1
            }
        }
        close(f)
        read[f] = 1
    }
    {
        if (!($3 in read))
            headings($3)
        if (!(($3 SUBSEP $4) in has)) {
            print "links-test: " $1 ": " $2 ": no such heading" > "/dev/stderr"
            bad = 1
        }
    }
    END { exit bad }' "$asked" || bad=1
[ "$bad" = 0 ] && echo "links-test: every relative link of the Markdown pages resolves"
exit "$bad"
