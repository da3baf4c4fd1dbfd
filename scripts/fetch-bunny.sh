#!/bin/sh
# SPDX-License-Identifier: MIT
# fetch-bunny.sh [DIR] -- the Stanford bunny from the npm package "bunny"
# (its low-resolution version) as Wavefront OBJ files in DIR (default
# data/, not committed):
#   bunny.obj     3,674 triangles
#   bunny-2.obj   58,784 triangles (every triangle split in four, twice)
#   bunny-4.obj   940,544 triangles (four times)
# Uses npm if present, else curl on the npm registry; needs a C compiler.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${1:-$root/data}
mkdir -p "$dir"
cd "$dir"
if [ -f bunny-4.obj ] && [ -f bunny-2.obj ] && [ -f bunny.obj ]; then
    exit 0
fi
if [ ! -f bunny-index.js ]; then
    tmp=$(mktemp -d)
    if command -v npm >/dev/null 2>&1; then
        (cd "$tmp" && npm pack bunny@1.0.1 --silent >/dev/null)
    elif command -v curl >/dev/null 2>&1; then
        curl -fsSL https://registry.npmjs.org/bunny/-/bunny-1.0.1.tgz \
            -o "$tmp/bunny-1.0.1.tgz"
    else
        echo "fetch-bunny: needs npm or curl (apt-get install -y curl)" >&2
        exit 1
    fi
    tar -xzf "$tmp/bunny-1.0.1.tgz" -C "$tmp"
    cp "$tmp/package/index.js" bunny-index.js
    rm -rf "$tmp"
fi
${CC:-cc} -O2 -o bunny2obj "$root/scripts/bunny2obj.c"
for level in 0 2 4; do
    name=bunny-$level.obj
    [ "$level" = 0 ] && name=bunny.obj
    ./bunny2obj bunny-index.js "$level" > "$name.tmp" && mv "$name.tmp" "$name"
    echo "fetch-bunny: $dir/$name ($(grep -c '^f ' "$name") triangles)" >&2
done
