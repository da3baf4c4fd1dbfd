#!/bin/sh
# SPDX-License-Identifier: MIT
# install-dirs.sh -- the directories make install creates, and only those,
# are what make uninstall removes (when empty).
#
#   install-dirs.sh create DESTDIR PREFIX LIST DIR...
#       makes each DIR (under DESTDIR) and adds to LIST (a file under
#       DESTDIR, in a DIR) those of them and of their parents below PREFIX
#       that did not exist, merged with what LIST already held.
#   install-dirs.sh remove DESTDIR PREFIX LIST DIR...
#       removes LIST, then each directory it named and each DIR, deepest
#       first, when it is empty; never PREFIX itself or anything outside it,
#       never a directory that is not empty.
set -eu
mode=$1 destdir=$2 prefix=$3 list=$4
shift 4

below_prefix() {
    case "$1" in "$prefix"/?*) return 0 ;; *) return 1 ;; esac
}

case "$mode" in
create)
    created=""
    for d in "$@"; do
        p=$d
        while below_prefix "$p" && [ ! -d "$destdir$p" ]; do
            created="$created
$p"
            p=$(dirname "$p")
        done
    done
    for d in "$@"; do
        install -d "$destdir$d"
    done
    {
        [ -f "$destdir$list" ] && cat "$destdir$list"
        printf '%s\n' "$created"
    } | sed '/^$/d' | sort -u > "$destdir$list.new"
    mv "$destdir$list.new" "$destdir$list"
    ;;
remove)
    dirs=""
    if [ -f "$destdir$list" ]; then
        dirs=$(cat "$destdir$list")
        rm -f "$destdir$list"
    fi
    # Deepest first: a parent is empty only once its children are gone.
    printf '%s\n' "$dirs" "$@" | sed '/^$/d' | sort -u |
        awk -F/ '{print NF "\t" $0}' | sort -rn | cut -f2- |
        while IFS= read -r d; do
            below_prefix "$d" || continue
            if [ -d "$destdir$d" ] && rmdir "$destdir$d" 2>/dev/null; then
                echo "uninstall: removed empty directory $destdir$d"
            fi
        done
    ;;
*)
    echo "install-dirs.sh: unknown mode '$mode'" >&2
    exit 2
    ;;
esac
