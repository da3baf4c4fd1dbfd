#!/bin/sh
# SPDX-License-Identifier: MIT
# check-spdx.sh -- every file of the project must say its licence: the line
# "SPDX-License-Identifier: MIT" in its first two lines (line 2 leaves room
# for a script's "#!" line).  Prints the files that lack it and fails.
#
# Which files: those git tracks, and the new ones it would track (not
# ignored), so a file is checked before its first commit.  Without git, or outside a git work tree (a
# tarball), every file under the top directory except what .gitignore
# leaves out of the repository (.git/, build/, data/, config.mak).
# Exempt: LICENSE, which is the licence text itself, binary files (the
# PNG pictures), which have no comment syntax -- a file counts as binary
# when grep -I (GNU and BSD grep) finds no text line in it -- and the
# fuzzers' inputs (fuzz/corpus/, fuzz/crashes/), which must stay the
# exact bytes a target reads (fuzz/seeds.sh, which writes the seeds,
# carries the line).
set -eu
cd "$(dirname "$0")/.."

list_files() {
    if command -v git >/dev/null 2>&1 &&
       git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
        git ls-files --cached --others --exclude-standard
    else
        find . \( -name .git -o -path ./build -o -path ./data \) -prune -o \
            -type f ! -name config.mak -print | sed 's|^\./||' | sort
    fi
}

# Which files to read, then one grep for the text ones (grep -I: binary
# files, and empty ones, have no text line) and one awk for their first
# two lines: three processes a file took seconds of CPU (issue 38).  The
# names go to awk as ./NAME, which it cannot take for an assignment.
missing=$(list_files | while IFS= read -r f; do
    [ -f "$f" ] || continue               # deleted in the work tree
    [ "$f" = LICENSE ] && continue
    case $f in fuzz/corpus/*|fuzz/crashes/*) continue;; esac
    printf './%s\n' "$f"
done | tr '\n' '\0' | xargs -0 -r grep -Il . | tr '\n' '\0' |
    xargs -0 -r awk '
        FNR == 1 { if (NR > 1 && !ok) print substr(prev, 3); prev = FILENAME; ok = 0 }
        FNR <= 2 && /SPDX-License-Identifier: MIT/ { ok = 1 }
        END { if (NR > 0 && !ok) print substr(prev, 3) }')
if [ -n "$missing" ]; then
    echo "license-test: no 'SPDX-License-Identifier: MIT' in the first two lines of:" >&2
    echo "$missing" | sed 's/^/  /' >&2
    exit 1
fi
echo "license-test: every text file carries the SPDX line"
