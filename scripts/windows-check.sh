#!/bin/sh
# SPDX-License-Identifier: MIT
# windows-check.sh WIN_BUILD BUILD -- make windows-check's run, after its
# build (doc/PLATFORMS.md): what MinGW-w64 built in WIN_BUILD, run under
# Wine, headless, in a fresh prefix (WIN_BUILD/wine), against the native
# build in BUILD.  Fails on the first thing that is wrong:
#   1. the DLL exports the API (ray.h's RAY_API functions, the names the
#      native shared library exports) and nothing else, and needs only
#      KERNEL32.dll and msvcrt.dll; no object of the library refers to
#      pthreads (the Win32 branch is the one built);
#   2. the Check suite: every suite in a process of its own, 0 failures,
#      0 crashes; then a suite that crashes on purpose, whose report must
#      name the test that was running;
#   3. the allocation-failure sweep (tests/faultsim.c);
#   4. the examples (through the DLL) at make check's sizes, their images
#      compared byte for byte (cmp) with the native ones; the renders at
#      other thread counts too, which must not change a byte;
#   5. (information) how the C runtime's math functions differ from
#      glibc's here (scripts/libm-probe.c).
# Prints how long each part took.
set -eu
win=${1:?usage: windows-check.sh WIN_BUILD BUILD}
native=${2:?usage: windows-check.sh WIN_BUILD BUILD}
host=${WIN_HOST:-x86_64-w64-mingw32}
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
start=$(date +%s)
step() {
    echo "windows-check: $* ($(($(date +%s) - start)) s)"
}

# ----------------------------------------------------- 1. the library
dll=$win/libray.dll
exports=$("$host-objdump" -p "$dll" |
    sed -n '/\[Ordinal\/Name Pointer\] Table/,/^$/p' |
    awk '/^[[:space:]]*\[ *[0-9]+\]/ {print $NF}' | sort)
api=$(sed -n 's/^RAY_API [^(]*[ *]\(ray_[a-z0-9_]*\)(.*/\1/p' include/ray.h | sort)
so_exports=$(nm -D --defined-only "$native/libray.so" |
    awk '$2 != "A" {print $3}' | sed 's/@.*//' | sort)
if [ "$exports" != "$api" ] || [ "$exports" != "$so_exports" ]; then
    echo "windows-check: libray.dll's exports are not ray.h's API:"
    echo "$exports" > "$win/exports.txt"
    echo "$api" > "$win/api.txt"
    diff "$win/api.txt" "$win/exports.txt" || true
    exit 1
fi
imports=$("$host-objdump" -p "$dll" | awk '/DLL Name:/ {print $3}' | sort | tr '\n' ' ')
if [ "$imports" != "KERNEL32.dll msvcrt.dll " ]; then
    echo "windows-check: libray.dll needs $imports(only KERNEL32.dll and msvcrt.dll expected)"
    exit 1
fi
if "$host-nm" -u "$win/libray.a" | grep -q pthread; then
    echo "windows-check: the library refers to pthreads:"
    "$host-nm" -A -u "$win/libray.a" | grep pthread
    exit 1
fi
step "libray.dll exports the $(echo "$api" | wc -l | tr -d ' ') functions of ray.h and nothing else, needs $imports; libray.a: no pthreads"

# ------------------------------------------------------------- Wine
export WINEPREFIX="$root/$win/wine" WINEDEBUG=-all WINEDLLOVERRIDES="winemenubuilder.exe=d"
unset DISPLAY WAYLAND_DISPLAY
rm -rf "$WINEPREFIX"
mkdir -p "$WINEPREFIX"
wineserver -p                     # one server for every run below
trap 'wineserver -k >/dev/null 2>&1 || true' EXIT INT TERM
# wine64 alone warns that wine32 is missing, and wineboot fails to start
# the 32-bit rundll32: true, and not needed; the prefix is what counts.
wineboot -i >"$win/wineboot.log" 2>&1 || true
if [ ! -d "$WINEPREFIX/drive_c/windows/system32" ]; then
    cat "$win/wineboot.log"
    echo "windows-check: wineboot made no prefix in $WINEPREFIX"
    exit 1
fi
step "a fresh Wine prefix in $WINEPREFIX ($(wine --version))"

# ----------------------------------------------------- 2. the suite
if ! wine "$win/tests/check_ray.exe" > "$win/check.log" 2>&1; then
    grep -v "^Running suite\|^100%" "$win/check.log" | tail -n 40
    echo "windows-check: the Check suite failed under Wine ($win/check.log)"
    exit 1
fi
grep "^SKIP\|^check_ray:" "$win/check.log" | tr -d '\r'
if RAY_CHECK_CRASH=1 wine "$win/tests/check_ray.exe" > "$win/crash.log" 2>&1 ||
   ! grep -q "suite crash CRASHED .* in test crash_should_name_the_test" "$win/crash.log" ||
   ! grep -q "^check_ray: 5 checks in 2 suites: 0 failed, 1 suites crashed" "$win/crash.log"; then
    cat "$win/crash.log"
    echo "windows-check: a crashing test was not reported by name"
    exit 1
fi
grep "CRASHED" "$win/crash.log" | tr -d '\r'
step "the Check suite passed; a crash names its test"

# ---------------------------------------------- 3. the fault sweep
if ! wine "$win/tests/faultsim.exe" > "$win/faultsim.log" 2>&1; then
    tail -n 30 "$win/faultsim.log"
    echo "windows-check: the allocation-failure sweep failed ($win/faultsim.log)"
    exit 1
fi
tail -n 1 "$win/faultsim.log" | tr -d '\r'
step "the allocation-failure sweep passed"

# --------------------------------------------------- 4. the examples
# ok WHAT COMMAND...: run it, its output kept in $log; a failure names
# the example and how it ended, with the end of its output, and stops
# the check (where set -e alone stopped it without a word).
ok() {
    what=$1
    shift
    if "$@" > "$log" 2>&1; then
        return 0
    else
        rc=$?
    fi
    echo "windows-check: $what failed (exit status $rc):"
    tail -n 20 "$log" | tr -d '\r'
    exit 1
}

# run DIR EXE SUFFIX: make check's renders by one build, images into DIR.
renders() {
    out=$1 run=$2 ex=$3 x=$4
    log=$out.log
    kind=${run:-native}
    mkdir -p "$out"
    rm -f "$out"/*.png
    ok "hello ($kind)" sh -c "cd '$out' && $run '$root/$ex/hello$x'"
    ok "material ($kind)" sh -c "cd '$out' && $run '$root/$ex/material$x'"
    ok "picking ($kind)" $run "$ex/picking$x"
    ok "game ($kind)" env RAY_GAME_FRAMES=10 $run "$ex/game$x"
    ok "primitives ($kind)" $run "$ex/primitives$x" "$out/primitives.png"
    ok "whitted ($kind)" $run "$ex/whitted$x" "$out/whitted.png" 64 48 1 2
    ok "cornell ($kind)" $run "$ex/cornell$x" "$out/cornell.png" 32 32 1 2
    ok "implicit ($kind)" $run "$ex/implicit$x" "$out/implicit.png" 48 30 1 2
    ok "textures ($kind)" $run "$ex/textures$x" doc/cornell.png \
        "$out/textures.png" 48 30 1 2
    ok "caustics ($kind)" env RAY_PHOTONS=50000 $run "$ex/caustics$x" \
        "$out/caustics.png" 48 36 1 2
    if [ -f data/teapot.bpt ]; then
        ok "teapot ($kind)" $run "$ex/teapot$x" data/teapot.bpt \
            "$out/teapot.png" 48 36 1 2
    fi
}
renders "$win/images-native" "" "$native/examples" ""
renders "$win/images" wine "$win/examples" .exe
same=0
for f in "$win/images-native"/*.png; do
    name=$(basename "$f")
    if ! cmp -s "$f" "$win/images/$name"; then
        "$native/tools/imgdiff" "$f" "$win/images/$name" || true
        echo "windows-check: $name differs from the native build's"
        exit 1
    fi
    same=$((same + 1))
done
# Other thread counts: not a byte may change (the native 2-thread image).
log=$win/images-threads.log
for t in 1 3 4; do
    ok "cornell at $t threads (wine)" wine "$win/examples/cornell.exe" \
        "$win/images/cornell-$t.png" 32 32 1 $t
    ok "caustics at $t threads (wine)" env RAY_PHOTONS=50000 \
        wine "$win/examples/caustics.exe" "$win/images/caustics-$t.png" \
        48 36 1 $t
    for name in cornell caustics; do
        if ! cmp -s "$win/images-native/$name.png" "$win/images/$name-$t.png"; then
            "$native/tools/imgdiff" "$win/images-native/$name.png" "$win/images/$name-$t.png" || true
            echo "windows-check: $name at $t threads differs"
            exit 1
        fi
    done
done
step "the examples ran; their $same images are the native ones byte for byte (cornell and caustics at 1 to 4 threads too)"

# Larger pictures (WINDOWS_LARGE=1; not in CI, about a minute more): 4
# samples a pixel, 2 threads, each picture's difference measured.
if [ "${WINDOWS_LARGE:-0}" = 1 ]; then
    large() {
        out=$1 run=$2 ex=$3 x=$4
        mkdir -p "$out"
        $run "$ex/whitted$x" "$out/whitted.png" 320 240 4 2 >/dev/null 2>&1
        $run "$ex/cornell$x" "$out/cornell.png" 200 200 4 2 >/dev/null 2>&1
        $run "$ex/implicit$x" "$out/implicit.png" 240 150 4 2 >/dev/null 2>&1
        $run "$ex/textures$x" doc/cornell.png "$out/textures.png" 240 150 4 2 >/dev/null 2>&1
        RAY_PHOTONS=200000 $run "$ex/caustics$x" "$out/caustics.png" 160 120 4 2 >/dev/null 2>&1
        if [ -f data/teapot.bpt ]; then
            $run "$ex/teapot$x" data/teapot.bpt "$out/teapot.png" 240 180 4 2 >/dev/null 2>&1
        fi
        if [ -f data/bunny.obj ]; then
            $run "$ex/mesh$x" data/bunny.obj "$out/mesh.png" 160 120 4 2 >/dev/null 2>&1
        fi
    }
    large "$win/large-native" "" "$native/examples" ""
    large "$win/large" wine "$win/examples" .exe
    differ=0
    for f in "$win/large-native"/*.png; do
        "$native/tools/imgdiff" "$f" "$win/large/$(basename "$f")" || differ=1
    done
    [ "$differ" = 0 ] || { echo "windows-check: a larger picture differs"; exit 1; }
    step "the larger pictures are the native ones too"
fi

# ---------------------------------------------- 5. the C runtime's libm
"$native/tools/libm-probe" > "$win/libm-native.txt"
wine "$win/tools/libm-probe.exe" > "$win/libm-windows.txt" 2>/dev/null
"$native/tools/libm-probe" --compare "$win/libm-native.txt" "$win/libm-windows.txt" | tr -d '\r'
"$native/tools/libm-probe" --threads | sed 's/^libm-probe: /libm-probe (native): /' > "$win/libm-threads.txt"
wine "$win/tools/libm-probe.exe" --threads 2>/dev/null | tr -d '\r' | sed 's/^libm-probe: /libm-probe (Windows): /' >> "$win/libm-threads.txt"
cat "$win/libm-threads.txt"
# WINDOWS_RECORD=1: keep these figures in bench/RESULTS-windows.md, whose
# table bench/run.sh copies into doc/PLATFORMS.md (as make bench does its
# own; bench-docs-test checks the copy).
if [ "${WINDOWS_RECORD:-0}" = 1 ]; then
    {
        echo "<!-- SPDX-License-Identifier: MIT -->"
        echo "# libray: the C runtime's math under Wine"
        echo
        echo "Command: \`make windows-check WINDOWS_RECORD=1\`; $("$host-gcc" --version | head -1),"
        echo "$(wine --version 2>/dev/null | tr -d '\r'); $(date -u +%Y-%m-%d)."
        echo
        echo "## libm: glibc against the Windows build under Wine"
        echo
        "$native/tools/libm-probe" --markdown "$win/libm-native.txt" "$win/libm-windows.txt" | tr -d '\r'
        echo
        sed 's/^/    /' "$win/libm-threads.txt"
    } > bench/RESULTS-windows.md
    bench/run.sh --splice "$native" >/dev/null
    echo "windows-check: wrote bench/RESULTS-windows.md and its table in doc/PLATFORMS.md"
fi
step "all passed"
