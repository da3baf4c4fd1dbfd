#!/bin/sh
# SPDX-License-Identifier: MIT
# check-snippets.sh BUILD PNG -- the code README.md and doc/*.md show
# builds and runs as shown, and the output they show is what it prints
# (make check, snippets-test).  A page marks a block on the line just
# before its opening fence:
#
#   <!-- program -->
#       before a ```c block: a complete program.  It is compiled alone,
#       with the library's warnings as errors (CC, CFLAGS: the Makefile's
#       ALL_CFLAGS), linked against BUILD/libray.a (LDFLAGS, LIBS), and
#       run in an empty directory: it must exit 0.
#   <!-- output -->
#       before a block: exactly what the page's last program printed on
#       stdout.
#   <!-- output: examples/NAME ARG... -->
#       before a block: exactly what BUILD/examples/NAME ARG... printed on
#       stdout, run in an empty directory.
#
# Every ```c block of README.md must be a program: a landing page shows
# nothing that does not build.  doc/ pages may also show fragments (an
# unmarked block: not compiled).  With PNG=0 a program or example that
# writes a PNG stops with RAY_ENOTSUP's text and exit status 1: accepted,
# and its output is not compared.  Prints each failure; fails if any.
set -eu
build=$1 png=$2
: "${CC:=cc}" "${CFLAGS:=}" "${LDFLAGS:=}" "${LIBS:=-lm -lpthread}"
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "$build" && pwd)
cd "$root"
LC_ALL=C
export LC_ALL

tmp=$(mktemp -d "${TMPDIR:-/tmp}/check-snippets.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM

# Split the pages into $tmp/N.c (programs) and $tmp/N.txt (outputs), with
# one line per marked block in $tmp/list: "program N PAGE:LINE",
# "output N PAGE:LINE" or "example N PAGE:LINE ARGS"; and "bare PAGE:LINE"
# for a ```c block of README.md without the program marker.

: > "$tmp/list"
for page in README.md doc/*.md; do
    awk -v page="$page" -v dir="$tmp" -v start="$(wc -l < "$tmp/list")" '
        BEGIN { n = start }
        in_block && /^```/ { in_block = 0; close(file); next }
        in_block { print > file; next }
        /^```/ {
            if (mark == "program" && $0 == "```c") {
                file = dir "/" ++n ".c"
                print "program", n, page ":" NR >> (dir "/list")
            } else if (mark == "output") {
                file = dir "/" ++n ".txt"
                if (args == "")
                    print "output", n, page ":" NR >> (dir "/list")
                else
                    print "example", n, page ":" NR, args >> (dir "/list")
            } else {
                if (page == "README.md" && $0 == "```c")
                    print "bare", 0, page ":" NR >> (dir "/list")
                file = "/dev/null"
            }
            printf "" > file
            in_block = 1; mark = ""; next
        }
        /^<!-- program -->$/ { mark = "program"; next }
        /^<!-- output -->$/ { mark = "output"; args = ""; next }
        /^<!-- output: .* -->$/ {
            mark = "output"; args = $0
            sub(/^<!-- output: /, "", args); sub(/ -->$/, "", args); next
        }
        { mark = "" }' "$page"
done

# SNIPPETS_EXTRACT=DIR: only copy the programs into DIR (N.c each), for
# scripts/check-amalgamation.sh to build them with doc/EMBEDDING.md's
# amalgamation lines.
if [ -n "${SNIPPETS_EXTRACT:-}" ]; then
    awk '$1 == "program" {print $2}' "$tmp/list" | while read -r n; do
        cp "$tmp/$n.c" "$SNIPPETS_EXTRACT/"
    done
    exit 0
fi

failures=0
programs=0
outputs=0
skipped=0
fail() {
    echo "snippets-test: $where: $*" >&2
    failures=$((failures + 1))
}

# run DIR CMD...: CMD in DIR (empty), stdout to $tmp/stdout, stderr to
# $tmp/stderr; sets $rc, and $skip when PNG=0 excuses a failure.
run() {
    dir=$1
    shift
    mkdir -p "$dir"
    rc=0
    (cd "$dir" && "$@") > "$tmp/stdout" 2> "$tmp/stderr" || rc=$?
    skip=
    if [ "$rc" -ne 0 ] && [ "$png" = 0 ] &&
       grep -q "not supported by this build" "$tmp/stderr"; then
        skip=1
    fi
}

last=
while read -r kind n where args; do
    case $kind in
    bare)
        fail "a C block without <!-- program -->: README.md shows only complete programs"
        ;;
    program)
        programs=$((programs + 1))
        last=
        # shellcheck disable=SC2086 # the flags are lists
        if ! $CC $CFLAGS -Werror -o "$tmp/$n" "$tmp/$n.c" $LDFLAGS \
                "$build/libray.a" $LIBS > "$tmp/cc.log" 2>&1; then
            fail "does not compile as shown:"
            sed 's/^/    /' "$tmp/cc.log" >&2
            continue
        fi
        run "$tmp/run$n" "$tmp/$n"
        if [ -n "$skip" ]; then
            last=skipped
        elif [ "$rc" -ne 0 ]; then
            fail "the program exits $rc:"
            sed 's/^/    /' "$tmp/stderr" >&2
        else
            cp "$tmp/stdout" "$tmp/last"
            last=$where
        fi
        ;;
    output|example)
        outputs=$((outputs + 1))
        if [ "$kind" = example ]; then
            # shellcheck disable=SC2086 # the example and its arguments
            set -- $args
            exe=$1
            shift
            run "$tmp/run$n" "$build/$exe" "$@"
            if [ -n "$skip" ]; then
                skipped=$((skipped + 1))
                continue
            elif [ "$rc" -ne 0 ]; then
                fail "$args exits $rc"
                continue
            fi
            got=$tmp/stdout
        elif [ "$last" = skipped ]; then
            skipped=$((skipped + 1))
            continue
        elif [ -z "$last" ]; then
            fail "an output block with no program above it that ran"
            continue
        else
            got=$tmp/last
        fi
        if ! cmp -s "$got" "$tmp/$n.txt"; then
            fail "the output shown is not what ${args:-the program above} prints (- shown, + printed):"
            diff "$tmp/$n.txt" "$got" | sed 's/^/    /' >&2 || true
        fi
        ;;
    esac
done < "$tmp/list"

if [ "$failures" -ne 0 ]; then
    echo "snippets-test: $failures failure(s)" >&2
    exit 1
fi
echo "snippets-test: $programs programs of README.md and doc/*.md compiled and run, $((outputs - skipped)) of $outputs outputs compared and shown as printed${png:+ (PNG=$png}$( [ "$skipped" = 0 ] || echo ": $skipped not compared, their program stopped at RAY_ENOTSUP" ))"
