#!/bin/sh
# SPDX-License-Identifier: MIT
# mutants.sh -- the project's own small mutation run (make mutants, issue 38).
#
# Applies each mutation of tests/mutants.txt, one at a time, to a scratch
# copy of the tree (never to the working files), rebuilds the library and
# the Check program there, runs the suites the list names for it, and says
# whether the suite failed (killed) or passed (survived).  It ends with the
# kill rate and the survivors.  A survivor that is not argued equivalent in
# the list is a gap in the tests: write the test that kills it.
#
# Usage: tests/mutants.sh [ID...]       (no ID: the whole list)
# Environment:
#   MUTANTS_LIST     the list (default tests/mutants.txt)
#   MUTANTS_DIR      the scratch copy (default /tmp/libray-mutants.$$,
#                    removed at the end unless MUTANTS_KEEP=1)
#   MUTANTS_JOBS     make -j and the Check workers (default 2)
#   MUTANTS_TIMEOUT  seconds for one suite under a mutant (default 600): a
#                    mutant that loops is killed by the timeout
#   MUTANTS_CFLAGS   the build's CFLAGS (default -O2)
#   CC               the compiler (default cc)
#   MUTANTS_CHECK_ONLY=1  only check the list against the tree (fast)
#
# The list: one mutation a line, fields separated by " :: ",
#   id :: file :: suites :: original :: replacement [:: equivalent: why]
# where original is a snippet of one line that occurs exactly once in the
# file (the script refuses the list otherwise, so a later edit of the file
# that moves or duplicates it is noticed), replacement what it becomes
# (may be empty: a dropped term), and suites the Check suites
# (tests/check_main.c) that cover the file, separated by spaces, run one
# after the other up to the first that fails (so the quickest first).  A sixth
# field starting "equivalent:" argues that the mutant cannot change any
# result; it is still run, and reported apart from the others.
#
# Exit status: 0 when every mutant that is not argued equivalent was
# killed (or the kill rate is at least MUTANTS_FLOOR percent, default 90),
# 1 otherwise, 2 on a broken list or a scratch build that fails.
set -u

root=$(cd "$(dirname "$0")/.." && pwd)
list=${MUTANTS_LIST:-$root/tests/mutants.txt}
case $list in /*) ;; *) list=$(pwd)/$list ;; esac
jobs=${MUTANTS_JOBS:-2}
limit=${MUTANTS_TIMEOUT:-600}
floor=${MUTANTS_FLOOR:-90}
cflags=${MUTANTS_CFLAGS:--O2}
cc=${CC:-cc}
scratch=${MUTANTS_DIR:-/tmp/libray-mutants.$$}
sep=$(printf '\037')

die() { echo "mutants: $*" >&2; exit 2; }

[ -f "$list" ] || die "no list $list"
command -v timeout >/dev/null 2>&1 || die "needs timeout(1) (coreutils)"

# The list, parsed once: comments and blank lines dropped, fields split on
# " :: " and joined with the unit separator (a tab would collapse an empty
# replacement under read).
parsed=$(mktemp) || exit 2
awk -v sep="$sep" '
    /^[ \t]*(#|$)/ { next }
    {
        n = split($0, f, / :: /)
        if (n < 5 || n > 6) {
            printf "mutants: %s line %d: %d fields, not 5 or 6\n", FILENAME, NR, n > "/dev/stderr"
            bad = 1
            next
        }
        if (n == 6 && f[6] !~ /^equivalent: ./) {
            printf "mutants: %s line %d: a sixth field must be \"equivalent: why\"\n", FILENAME, NR > "/dev/stderr"
            bad = 1
            next
        }
        if (seen[f[1]]++) {
            printf "mutants: %s line %d: id %s twice\n", FILENAME, NR, f[1] > "/dev/stderr"
            bad = 1
        }
        printf "%s%s%s%s%s%s%s%s%s%s%s\n", f[1], sep, f[2], sep, f[3], sep, f[4], sep, f[5], sep, (n == 6 ? f[6] : "")
    }
    END { exit bad }' "$list" > "$parsed" || { rm -f "$parsed"; die "broken list $list"; }

# Replaces the one occurrence of $M_ORIG in file $1 by $M_REPL (through
# the environment: awk's -v would interpret backslashes); fails when the
# snippet occurs other than once.
mutate() {
    awk '
        BEGIN { o = ENVIRON["M_ORIG"]; r = ENVIRON["M_REPL"]; n = 0 }
        {
            line = $0; out = ""
            while ((i = index(line, o)) > 0) {
                n++
                out = out substr(line, 1, i - 1) r
                line = substr(line, i + length(o))
            }
            print out line
        }
        END { if (n != 1) { printf "%d occurrences\n", n > "/dev/stderr"; exit 1 } }' \
        "$1" > "$1.mutant" && mv "$1.mutant" "$1"
}

# Check every snippet against the working tree first, so that a stale
# list fails at once rather than an hour in.
while IFS=$sep read -r id file suites orig repl note; do
    [ -f "$root/$file" ] || die "$id: no file $file"
    cp "$root/$file" "$parsed.probe"
    M_ORIG=$orig M_REPL=$repl mutate "$parsed.probe" 2>"$parsed.err" ||
        die "$id: the snippet of $file occurs $(cat "$parsed.err"), not once: '$orig'"
    cmp -s "$root/$file" "$parsed.probe" && die "$id: the replacement changes nothing"
done < "$parsed"
rm -f "$parsed.probe" "$parsed.err"
if [ "${MUTANTS_CHECK_ONLY:-0}" = 1 ]; then
    echo "mutants: $(wc -l < "$parsed") mutants, every snippet found once"
    rm -f "$parsed"
    exit 0
fi

# Only the mutants asked for.
if [ $# -gt 0 ]; then
    for want in "$@"; do
        grep -q "^$want$sep" "$parsed" || die "no mutant $want in $list"
    done
    keep=$(mktemp) || exit 2
    for want in "$@"; do grep "^$want$sep" "$parsed"; done > "$keep"
    mv "$keep" "$parsed"
fi

# The scratch copy: the files git tracks or would track (the working
# tree's state, uncommitted edits included), no build outputs.
[ -e "$scratch" ] && die "$scratch exists: remove it or set MUTANTS_DIR"
mkdir -p "$scratch" || die "cannot create $scratch"
cleanup() {
    rm -f "$parsed"
    [ "${MUTANTS_KEEP:-0}" = 1 ] || rm -rf "$scratch"
}
trap cleanup EXIT
trap 'exit 130' INT TERM
(cd "$root" && git ls-files -z -c -o --exclude-standard |
    xargs -0 sh -c 'for f; do [ -e "$f" ] && printf "%s\0" "$f"; done' sh |
    tar --null -T - -cf -) | tar -xf - -C "$scratch" || die "cannot copy the tree"

build=build/mutants
bin=$build/tests/check_ray
cd "$scratch" || exit 2
mk() { make -j"$jobs" CC="$cc" BUILD=$build CFLAGS="$cflags" "$bin" >"$scratch/make.log" 2>&1; }

echo "mutants: building the unmutated tree in $scratch ($cc $cflags)"
mk || { tail -n 30 "$scratch/make.log"; die "the unmutated tree does not build"; }

# Which objects each file goes into: gcc -MM on every source, once.
deps=$scratch/deps
: > "$deps"
for src in src/*/*.c tests/check_*.c; do
    case $src in
    src/*) obj=$build/obj/${src#src/} ;;
    *) obj=$build/tests/obj/${src#tests/} ;;
    esac
    [ -f "${obj%.c}.o" ] || continue
    printf '%s:' "${obj%.c}.o" >> "$deps"
    $cc -MM -Iinclude -Isrc -Iexamples -Ibench -Itests \
        $(pkg-config --cflags check libpng 2>/dev/null) "$src" |
        tr -d '\\\n' | sed 's/^[^:]*://' >> "$deps"
    echo >> "$deps"
done
objs=$(cut -d: -f1 "$deps")
# The unmutated objects, restored after each mutant.
mkdir -p "$scratch/pristine"
for o in $objs; do
    mkdir -p "$scratch/pristine/$(dirname "$o")"
    cp -p "$o" "$scratch/pristine/$o"
done

# All the suites at once, shared among the workers (the unmutated run),
# MUTANTS_TIMEOUT seconds a suite.
run_suites() {
    CK_TIMEOUT_MULTIPLIER=${CK_TIMEOUT_MULTIPLIER:-10} RAY_CHECK_JOBS=$jobs \
        RAY_CHECK_SUITES="$1" timeout $((limit * $(echo $1 | wc -w))) "$bin" \
        >"$scratch/run.log" 2>&1
}

# A mutant's suites one after the other, in the list's order, up to the
# first that fails: a killed mutant rarely needs them all (so the list
# names the quickest suite that covers the file first).
run_mutant() {
    for suite in $1; do
        CK_TIMEOUT_MULTIPLIER=${CK_TIMEOUT_MULTIPLIER:-10} RAY_CHECK_JOBS=1 \
            CK_RUN_SUITE=$suite timeout "$limit" "$bin" >"$scratch/run.log" 2>&1 || return
    done
}

# The listed suites must pass unmutated, or a "kill" means nothing.
all_suites=$(cut -d"$sep" -f3 "$parsed" | tr ' ' '\n' | sort -u | tr '\n' ' ')
echo "mutants: the unmutated suites: $all_suites"
run_suites "$all_suites" ||
    { tail -n 30 "$scratch/run.log"; die "the listed suites fail unmutated"; }

total=0 killed=0 equiv=0 equiv_killed=0 broken=0
survivors=
t0=$(date +%s)
while IFS=$sep read -r id file suites orig repl note; do
    total=$((total + 1))
    # Back to the unmutated tree: the source, then its objects.
    for o in $objs; do cp -p "$scratch/pristine/$o" "$o"; done
    cp "$root/$file" "$file"
    M_ORIG=$orig M_REPL=$repl mutate "$file" || die "$id: cannot apply"
    # Every object the file does not go into is made newer than it, so
    # make rebuilds only those it goes into (the Makefile has every
    # object depend on every private header).
    for o in $(grep -v "[ ]$file\( \|$\)" "$deps" | cut -d: -f1); do touch "$o"; done
    s0=$(date +%s)
    if ! mk; then
        verdict="BUILD FAILED"
        broken=$((broken + 1))
    elif run_mutant "$suites"; then
        verdict=survived
    else
        rc=$?
        verdict=killed
        [ $rc -ge 124 ] && [ $rc -le 137 ] && verdict="killed (rc $rc: timeout or signal)"
    fi
    case $verdict in
    killed*)
        killed=$((killed + 1))
        [ -n "$note" ] && equiv_killed=$((equiv_killed + 1)) ;;
    survived)
        if [ -n "$note" ]; then
            equiv=$((equiv + 1))
            verdict="survived (argued equivalent)"
        else
            survivors="$survivors $id"
        fi ;;
    esac
    printf 'mutant %-28s %-36s %s (%ss)\n' "$id" "$file" "$verdict" $(($(date +%s) - s0))
    cp "$root/$file" "$file"
done < "$parsed"
for o in $objs; do cp -p "$scratch/pristine/$o" "$o"; done

counted=$((total - equiv))
rate=0
[ $counted -gt 0 ] && rate=$((100 * killed / counted))
echo "mutants: $killed of $total killed, $equiv argued equivalent (survived)," \
    "$equiv_killed argued equivalent but killed, $broken did not build;" \
    "kill rate $killed/$counted = $rate% of the mutants not argued equivalent" \
    "($(($(date +%s) - t0)) s)"
if [ -n "$survivors" ]; then
    echo "mutants: survivors not argued equivalent:$survivors"
fi
[ $broken -eq 0 ] || exit 2
[ -z "$survivors" ] || [ $rate -ge "$floor" ] || exit 1
exit 0
