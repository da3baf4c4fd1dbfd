#!/bin/sh
# SPDX-License-Identifier: MIT
# deps.sh -- make sure the Debian packages a make target needs are present.
#
# Usage: scripts/deps.sh [--check | --install] NEED...   where NEED is one of
#   pkg-config  libpng  check  mandoc  gnuplot (make bench's plot)
#   povray (bench/whitted.c's other side; the Makefile treats it as optional)
#   mpi (OpenMPI's mpicc and mpirun: make mpi-demo)
#   cmake, abigail (abidw and abidiff): make check's CMake subproject and
#   ABI tests (mk/release.mk)
#   gcovr (make coverage's report)
# Each present dependency costs one quick probe.  With --check (the
# default; plain make and make install), missing ones are reported with
# the exact apt-get command and the script fails.  With --install (only
# the showcase targets: make check, demo, bench...), they are installed
# with apt-get when we are root (or have password-less sudo), announced in
# one line; otherwise the script prints the command and fails.
set -u

mode=check
case "${1:-}" in
--check) mode=check; shift ;;
--install) mode=install; shift ;;
esac

missing=""
for need in "$@"; do
    case "$need" in
    pkg-config) command -v pkg-config >/dev/null 2>&1 || missing="$missing pkg-config" ;;
    libpng)     { command -v pkg-config >/dev/null 2>&1 && pkg-config --exists libpng; } \
                    || missing="$missing libpng-dev" ;;
    check)      { command -v pkg-config >/dev/null 2>&1 && pkg-config --exists check; } \
                    || missing="$missing check" ;;
    mandoc)     command -v mandoc >/dev/null 2>&1 || missing="$missing mandoc" ;;
    gnuplot)    command -v gnuplot >/dev/null 2>&1 || missing="$missing gnuplot-nox" ;;
    povray)     command -v povray >/dev/null 2>&1 || missing="$missing povray" ;;
    mpi)        { command -v mpicc >/dev/null 2>&1 && command -v mpirun >/dev/null 2>&1; } \
                    || missing="$missing libopenmpi-dev openmpi-bin" ;;
    cmake)      command -v cmake >/dev/null 2>&1 || missing="$missing cmake" ;;
    gcovr)      command -v gcovr >/dev/null 2>&1 || missing="$missing gcovr" ;;
    abigail)    { command -v abidw >/dev/null 2>&1 && command -v abidiff >/dev/null 2>&1; } \
                    || missing="$missing abigail-tools" ;;
    *)          echo "deps.sh: unknown dependency '$need'" >&2; exit 2 ;;
    esac
done
[ -z "$missing" ] && exit 0
# pkg-config is needed to probe the libraries, so bring it along.
case "$missing" in *pkg-config*) ;; *) command -v pkg-config >/dev/null 2>&1 || missing="pkg-config$missing" ;; esac
missing=$(echo $missing)

if [ "$mode" = check ]; then
    echo "libray: missing Debian packages: $missing; install them with: sudo apt-get install -y $missing" >&2
    echo "libray: (make check, make demo and make bench install them themselves when run as root)" >&2
    exit 1
fi
if [ "$(id -u)" = 0 ]; then
    sudo=""
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    sudo="sudo"
else
    echo "libray: missing Debian packages: $missing; install them with: sudo apt-get install -y $missing" >&2
    exit 1
fi
if ! command -v apt-get >/dev/null 2>&1; then
    echo "libray: missing $missing and no apt-get here; install the equivalent packages" >&2
    exit 1
fi
echo "libray: installing missing Debian packages: $missing" >&2
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq >/dev/null 2>&1
if ! $sudo apt-get install -y -qq $missing >/dev/null 2>&1; then
    echo "libray: 'apt-get install -y $missing' failed; run it by hand to see why" >&2
    exit 1
fi
