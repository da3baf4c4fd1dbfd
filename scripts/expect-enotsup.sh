#!/bin/sh
# SPDX-License-Identifier: MIT
# expect-enotsup.sh PROGRAM [ARG...] -- in a library built with PNG=0, an
# example that writes or reads a PNG must stop with exit status 1 and
# ray_strerror(RAY_ENOTSUP)'s text on stderr, not crash or succeed.
set -u
want="not supported by this build"
err=$("$@" 2>&1 >/dev/null)
rc=$?
if [ "$rc" -ne 1 ] || ! printf '%s\n' "$err" | grep -q "$want"; then
    echo "expect-enotsup: $*: exit $rc, stderr:" >&2
    printf '%s\n' "$err" | sed 's/^/  /' >&2
    echo "expect-enotsup: wanted exit 1 and '$want'" >&2
    exit 1
fi
echo "expect-enotsup: $1: exit 1, $(printf '%s\n' "$err" | grep "$want" | head -n 1)"
