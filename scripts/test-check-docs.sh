#!/bin/sh
# SPDX-License-Identifier: MIT
# test-check-docs.sh -- scripts/check-docs.sh catches the drift it is for.
#
# A check that passes on the real tree proves nothing by itself: here
# each case copies include/ray.h and man/ to a temporary directory, breaks
# one thing the way an edit would, and requires check-docs.sh to fail
# with a message naming the function (or type) it broke.  Needs MLINKS
# as "make docs-test" passes it.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
links=${MLINKS:?"run as make docs-test (needs MLINKS)"}
cases=0

# expect WHAT MESSAGE FILE SED-SCRIPT [MLINKS]: after applying SED-SCRIPT
# to FILE (under the copy), check-docs.sh fails and prints MESSAGE.
expect() {
    rm -rf "$tmp/man" "$tmp/ray.h"
    cp -R "$top/man" "$tmp/man"
    cp "$top/include/ray.h" "$tmp/ray.h"
    sed -e "$4" "$tmp/$3" > "$tmp/edited"
    if cmp -s "$tmp/edited" "$tmp/$3"; then
        echo "test-check-docs: $1: the edit of $3 changed nothing (update this test)" >&2
        exit 1
    fi
    mv "$tmp/edited" "$tmp/$3"
    if out=$(MLINKS=${5:-$links} "$top/scripts/check-docs.sh" "$tmp/ray.h" "$tmp/man" 2>&1); then
        echo "test-check-docs: $1: check-docs.sh passed, it should have failed" >&2
        exit 1
    fi
    case "$out" in
    *"$2"*) cases=$((cases + 1)) ;;
    *) printf 'test-check-docs: %s: expected "%s" in:\n%s\n' "$1" "$2" "$out" >&2
       exit 1 ;;
    esac
}

expect "a parameter renamed in a page" "ray_polygon: parameter 2 differs" \
    man/man3/ray_polygon.3 's/^\.Fa "const ray_vec3 \*v"$/.Fa "const ray_vec3 *verts"/'
expect "a parameter dropped from a page" "ray_refract: 4 parameters" \
    man/man3/ray_reflect.3 '/^\.Fa "double eta"$/d'
expect "a return type changed in the header" "ray_fresnel: return type differs" \
    ray.h 's/^RAY_API double ray_fresnel(/RAY_API float ray_fresnel(/'
expect "a new function without a page" "ray_cone is in no man page SYNOPSIS" \
    ray.h '/^RAY_API double ray_fresnel(/a\
RAY_API int ray_cone(const ray_ray *r, ray_vec3 apex,\
                     ray_vec3 base, ray_hit *hit);'
expect "a page showing a function ray.h lacks" "the SYNOPSIS shows ray_refraction" \
    man/man3/ray_reflect.3 's/^\.Fo ray_refract$/.Fo ray_refraction/'
expect "a function missing from its page's NAME" \
    "ray_refract is in the SYNOPSIS but not in the NAME section" \
    man/man3/ray_reflect.3 '/^\.Nm ray_refract ,$/d'
expect "a struct member changed in a page's copy" "its copy of ray_light differs" \
    man/man3/ray_scene_add_sphere.3 's/^    double radius;  /    float radius;   /'
expect "a link missing from MLINKS" "ray_fresnel: documented on" \
    man/man3/ray_reflect.3 's/^\.Nd mirror direction/.Nd the mirror direction/' \
    "$(echo "$links" | sed 's/ray_reflect:ray_fresnel//')"
echo "docs-test: check-docs.sh fails as it should on $cases kinds of drift (scripts/test-check-docs.sh)"
