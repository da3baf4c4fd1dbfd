#!/bin/sh
# SPDX-License-Identifier: MIT
# check-amalgamation.sh DIR BUILD PNG -- make amalgamation-test (part of
# make check): the one-file library DIR/libray.c (with DIR/ray.h), which
# make amalgamation writes, is the library.
#
#  0. doc/EMBEDDING.md's amalgamation lines, as written (read from the
#     page by scripts/doc-block.sh), in a directory holding libray.c, ray.h
#     and app.c, build and link each program of README.md and doc/ that
#     snippets-test runs (check-snippets.sh SNIPPETS_EXTRACT), and
#     tests/cmake-consumer/main.c, as app.c; each runs, and the consumer
#     writes a PNG exactly where pkg-config finds libpng.  libray.c is
#     compiled once, for the first; the lines that compile it are left
#     out for the others.  cc is $CC (LDFLAGS after it).
#  1. It builds with the command doc/EMBEDDING.md gives for no libpng, and
#     nothing else: $CC -std=c99 -O2 -c libray.c; tests/cmake-consumer/main.c
#     linked with that object (and -lm -lpthread) runs, without libpng.
#  2. With gcc and with clang (each where installed), in GNU C mode
#     (-std=gnu99, where gcc fuses a*b+c into an FMA by default) and with
#     FMA instructions available (-mfma on x86), under the library's
#     warnings (WARN, and -Werror when CFLAGS has it): the object is byte
#     for byte the one -ffp-contract=off gives, so the file's own pragmas
#     (scripts/amalgamation-prologue.h) keep the arithmetic uncontracted
#     whatever the flags.
#  3. With PNG=1: built with -DRAY_PNG=1 and CFLAGS (step 0's object where
#     that is the same code), the examples linked
#     against it render the pictures the Makefile's examples render,
#     compared with cmp (make check's sizes); built with -mavx2 too (on
#     an x86 CPU with AVX2), whitted's picture again.
#
# CC, CFLAGS, LDFLAGS, WARN, ALL_CFLAGS (the examples' flags), PNG_CFLAGS
# and LIBS come from the environment (the Makefile's); EXAMPLE_OBJ, where
# set, is the directory of the Makefile's example objects (NAME.o), which
# step 3 links with the amalgamation rather than compiling each example
# again: the same source, flags and header (ALL_CFLAGS's -Iinclude comes
# before -IDIR, and DIR/ray.h is include/ray.h, checked), so the same
# object.
set -eu
dir=$1 build=$2 png=$3
: "${CC:=cc}" "${CFLAGS:=}" "${LDFLAGS:=}" "${WARN:=}" "${PNG_CFLAGS:=}"
: "${LIBS:=-lm -lpthread}" "${ALL_CFLAGS:=-std=c99 -Iinclude}"
top=$(pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/libray-amalgamation-test.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "amalgamation-test: $*" >&2; exit 1; }
werror=""
case " $CFLAGS " in *" -Werror "*) werror=-Werror ;; esac
# AMALG_PART, which steps run (issue 38): "check", make check's, steps 0,
# 1 and 3 (the pages' lines, the plain command, the examples' pictures);
# "long", make check-long's (which CI runs after make check), steps 2
# and 4, five more compiles of the whole library (gcc and clang each
# twice, -mavx2), half of make check's amalgamation-test; "all", the
# default, every step.
part=${AMALG_PART:-all}
want() {
    case $part:$1 in
    all:*|check:[013]|long:[24]) return 0 ;;
    esac
    return 1
}

# 0. The page's lines, as written, for every program the pages show.
if want 0; then
    mkdir "$tmp/doc" "$tmp/programs"
    cp "$dir/libray.c" "$dir/ray.h" "$tmp/doc/"
    "$top/scripts/doc-block.sh" amalgamation > "$tmp/doc-lines" ||
        fail "doc/EMBEDDING.md shows no amalgamation lines"
    SNIPPETS_EXTRACT="$tmp/programs" "$top/scripts/check-snippets.sh" "$build" "$png"
    cp "$top/tests/cmake-consumer/main.c" "$tmp/programs/consumer.c"
    if pkg-config --exists libpng 2>/dev/null; then found=1; else found=0; fi
    # shellcheck disable=SC2016 # expanded by the sh that runs the line
    printf '%s\n' 'cc() { command $CC "$@" $LDFLAGS; }' > "$tmp/first.sh"
    cp "$tmp/first.sh" "$tmp/next.sh"
    cat "$tmp/doc-lines" >> "$tmp/first.sh"
    grep -v -e '-c libray\.c' "$tmp/doc-lines" >> "$tmp/next.sh"
    script=first.sh
    count=0
    for prog in "$tmp/programs"/*.c; do
        name=$(basename "$prog")
        cp "$prog" "$tmp/doc/app.c"
        cp "$tmp/$script" "$tmp/doc/"
        rm -f "$tmp/doc/a.out"
        (cd "$tmp/doc" && CC="$CC" LDFLAGS="$LDFLAGS" sh -e "$script") ||
            fail "doc/EMBEDDING.md's amalgamation lines failed on $name as app.c"
        script=next.sh
        mkdir "$tmp/doc/run-$name"
        arg=""
        [ "$name" != consumer.c ] || [ "$found" = 0 ] || arg=out.png
        # shellcheck disable=SC2086 # no argument, or one
        (cd "$tmp/doc/run-$name" && ../a.out $arg >/dev/null) ||
            fail "$name, built by doc/EMBEDDING.md's amalgamation lines, failed${arg:+ (the consumer writing a PNG: libpng is found)}"
        count=$((count + 1))
    done
    echo "amalgamation-test: doc/EMBEDDING.md's amalgamation lines, as written: $count programs (the pages' and the consumer) built and ran; PNG calls $([ $found = 1 ] && echo on, libpng found || echo off, no libpng)"
fi

# 1. The documented command, alone.
# shellcheck disable=SC2086 # the flags are lists
if want 1; then
    $CC -std=c99 -O2 -c "$dir/libray.c" -o "$tmp/plain.o" ||
        fail "$CC -std=c99 -O2 -c libray.c failed"
    # shellcheck disable=SC2086
    $CC -std=c99 -I"$dir" -DEXPECT_PNG=0 "$top/tests/cmake-consumer/main.c" \
        "$tmp/plain.o" -o "$tmp/consumer" -lm -lpthread $LDFLAGS ||
        fail "the consumer does not link with the amalgamation"
    "$tmp/consumer" "$tmp/consumer.png" >/dev/null ||
        fail "the consumer linked with the amalgamation failed"
    echo "amalgamation-test: $CC -std=c99 -O2 -c libray.c: built; the consumer linked with it ran (no libpng)"
fi

# 2. gcc and clang, GNU mode, FMA available: the pragmas hold.
if want 2; then
    for cc in gcc clang; do
        command -v "$cc" >/dev/null 2>&1 || {
            echo "amalgamation-test: no $cc here: its compile skipped"; continue; }
        fma=""
        case $($cc -dumpmachine 2>/dev/null) in
        x86_64-*|i?86-*|amd64-*) fma=-mfma ;;
        esac
        # shellcheck disable=SC2086
        $cc -std=gnu99 -O2 $fma $WARN $werror -c "$dir/libray.c" \
            -o "$tmp/$cc-pragma.o" || fail "$cc $WARN: libray.c does not compile cleanly"
        # shellcheck disable=SC2086
        $cc -std=gnu99 -O2 $fma -ffp-contract=off -c "$dir/libray.c" \
            -o "$tmp/$cc-flag.o" || fail "$cc -ffp-contract=off failed"
        cmp -s "$tmp/$cc-pragma.o" "$tmp/$cc-flag.o" ||
            fail "$cc -std=gnu99 -O2 $fma: the object differs from -ffp-contract=off's: the amalgamation's pragma does not stop contraction"
        echo "amalgamation-test: $cc -std=gnu99 -O2 $fma, the library's warnings${werror:+ as errors}: clean, and byte-identical to -ffp-contract=off"
    done
fi

# 3. The examples on it, against the Makefile's pictures.
if [ "$png" != 1 ]; then
    echo "amalgamation-test: PNG=0: no pictures to compare"
    exit 0
fi
# Step 0's object, from the page's line (-std=c99 -O2 -DRAY_PNG=1 and
# libpng's flags), is this one whenever CFLAGS holds nothing but -O2, -g
# and -Werror (the default, and CI's): debugging information changes no
# instruction, and the warnings as errors are held in step 2, under the
# library's warnings, by make check-long.  Used as it is, not compiled a
# third time (issue 38: 11 s of one core).
flags=""
for f in $CFLAGS; do
    case $f in -g|-Werror) ;; *) flags="$flags $f" ;; esac
done
if want 0 && [ "$found" = 1 ] && [ "$flags" = " -O2" ] && [ -z "$LDFLAGS" ] &&
   [ -f "$tmp/doc/libray.o" ]; then
    cp "$tmp/doc/libray.o" "$tmp/libray.o"
    built="$CC -std=c99 -O2 -DRAY_PNG=1 (step 0's object, for CFLAGS $CFLAGS)"
else
    built="$CC -std=c99 $CFLAGS -DRAY_PNG=1"
    # shellcheck disable=SC2086
    $CC -std=c99 $CFLAGS -DRAY_PNG=1 $PNG_CFLAGS -c "$dir/libray.c" \
        -o "$tmp/libray.o" || fail "libray.c -DRAY_PNG=1 failed"
fi
if want 3; then
    mkdir "$tmp/amalg" "$tmp/make"
    # name and arguments (OUT: the picture), as make check runs them.
    set -- "hello" "material" "primitives OUT" "whitted OUT 64 48 1 2" \
        "cornell OUT 32 32 1 2" "implicit OUT 48 30 1 2" \
        "textures $top/doc/cornell.png OUT 48 30 1 2"
    reuse=0 objs=""
    if [ -n "${EXAMPLE_OBJ:-}" ] && cmp -s "$dir/ray.h" "$top/include/ray.h"; then
        reuse=1
        case $EXAMPLE_OBJ in /*) objs=$EXAMPLE_OBJ ;; *) objs=$top/$EXAMPLE_OBJ ;; esac
    fi
    for run in "$@"; do
        name=${run%% *}
        if [ "$reuse" = 1 ] && [ -f "$objs/$name.o" ]; then
            # shellcheck disable=SC2086
            $CC $CFLAGS $LDFLAGS -o "$tmp/amalg/$name" \
                "$objs/$name.o" "$tmp/libray.o" $LIBS ||
                fail "examples/$name.c does not link with the amalgamation"
        else
            # shellcheck disable=SC2086
            $CC $ALL_CFLAGS -I"$dir" $LDFLAGS -o "$tmp/amalg/$name" \
                "$top/examples/$name.c" "$tmp/libray.o" $LIBS ||
                fail "examples/$name.c does not link with the amalgamation"
        fi
        for how in make amalg; do
            exe=$tmp/$how/$name
            [ "$how" = make ] && exe=$top/$build/examples/$name
            args=$(echo "$run" | sed "s|OUT|$tmp/$how/$name.png|; s|^$name||")
            # The examples without arguments write NAME.png where they run.
            # shellcheck disable=SC2086
            (cd "$tmp/$how" && "$exe" $args >/dev/null 2>&1) ||
                fail "$how: $name failed"
        done
        cmp "$tmp/make/$name.png" "$tmp/amalg/$name.png" ||
            fail "$name: the picture differs between the Makefile's library and the amalgamation"
    done
    how=""
    [ "$reuse" = 0 ] || how=" (the Makefile's objects of them)"
    echo "amalgamation-test: $built: examples hello material primitives whitted cornell implicit textures$how linked with it; their pictures byte-identical to the Makefile's"
fi

# 4. The documented -mavx2 switch (x86 CPUs with AVX2): the whole library
#    built for AVX2, packets included, renders the same picture.
if want 4; then
    case $($CC -dumpmachine 2>/dev/null) in
    x86_64-*|i?86-*|amd64-*)
        if grep -qw avx2 /proc/cpuinfo 2>/dev/null; then
            # The Makefile's picture, which step 3 rendered where it ran.
            [ -f "$tmp/make/whitted.png" ] || {
                mkdir -p "$tmp/make"
                "$top/$build/examples/whitted" "$tmp/make/whitted.png" 64 48 1 2 \
                    >/dev/null 2>&1 || fail "make: whitted failed"; }
            # shellcheck disable=SC2086
            $CC -std=c99 $CFLAGS -mavx2 -DRAY_PNG=1 $PNG_CFLAGS -c \
                "$dir/libray.c" -o "$tmp/avx2.o" || fail "libray.c -mavx2 failed"
            # shellcheck disable=SC2086
            $CC -I"$dir" $ALL_CFLAGS $LDFLAGS -o "$tmp/whitted-avx2" \
                "$top/examples/whitted.c" "$tmp/avx2.o" $LIBS
            "$tmp/whitted-avx2" "$tmp/whitted-avx2.png" 64 48 1 2 >/dev/null 2>&1 ||
                fail "whitted on the -mavx2 amalgamation failed"
            cmp "$tmp/make/whitted.png" "$tmp/whitted-avx2.png" ||
                fail "-mavx2: whitted's picture differs from the Makefile's"
            echo "amalgamation-test: -mavx2: whitted's picture byte-identical to the Makefile's"
        fi ;;
    esac
fi
