#!/bin/sh
# SPDX-License-Identifier: MIT
# test-check-layers.sh OBJDIR OBJECT... -- check-layers.sh fails as it
# should.  Each case builds a scratch tree (sources for the include check,
# tiny objects compiled here for the call checks) with one offence and
# expects check-layers.sh to exit 1 naming it; the first case is clean
# and must pass.  The last cases add one offending object to the real
# library's objects (OBJECT..., in OBJDIR), which pass alone.
#
# The cases include the circle issue 26 opened: scene/instance.o calling
# ray__child_query in query/intersect.o, which called ray__scene_stale
# back in scene/instance.o, with scene/kinds.o dispatching an instance's
# test to scene/instance.o.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
check=$root/scripts/check-layers.sh
objdir=$1
shift
CC=${CC:-cc}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/test-check-layers.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM
cases=0

# obj LAYER/NAME 'C source': compile the source into case tree $t.
obj() {
    mkdir -p "$t/obj/$(dirname "$1")" "$t/src/$(dirname "$1")"
    printf '%s\n' "$2" > "$t/src/$1.c"
    $CC -c -o "$t/obj/$1.o" "$t/src/$1.c"
}

# new_case NAME: an empty case tree.
new_case() {
    t=$tmp/$1
    mkdir -p "$t/src" "$t/obj"
    cases=$((cases + 1))
}

# expect_fail TEXT [OBJECT...]: check-layers.sh on $t exits 1 and says TEXT.
expect_fail() {
    text=$1
    shift
    if SRCDIR=$t/src "$check" "$t/obj" "$@" > "$t/out" 2>&1; then
        echo "test-check-layers: $(basename "$t"): passed, expected a failure:"
        cat "$t/out"
        exit 1
    fi
    grep -qF -e "$text" "$t/out" || {
        echo "test-check-layers: $(basename "$t"): no \"$text\" in:"
        cat "$t/out"
        exit 1
    }
}

# A clean tree passes.
new_case clean
obj core/vec 'int ray__core_fn(void); int ray__core_fn(void) { return 1; }'
obj scene/store 'int ray__core_fn(void); int ray__store_fn(void);
int ray__store_fn(void) { return ray__core_fn(); }'
if ! SRCDIR=$t/src "$check" "$t/obj" > "$t/out" 2>&1; then
    echo "test-check-layers: a clean tree failed:"
    cat "$t/out"
    exit 1
fi

# Issue 26's circle, as the objects were before it was opened.
new_case instance-circle
obj query/intersect 'int ray__scene_stale(void); int ray__child_query(void);
int ray__prim_intersect(void);
int ray__child_query(void) { return ray__scene_stale() + ray__prim_intersect(); }'
obj scene/instance 'int ray__child_query(void); int ray__scene_stale(void);
int ray__instance_intersect(void);
int ray__scene_stale(void) { return 0; }
int ray__instance_intersect(void) { return ray__child_query(); }'
obj scene/kinds 'int ray__instance_intersect(void); int ray__prim_intersect(void);
int ray__prim_intersect(void) { return ray__instance_intersect(); }'
expect_fail "scene/instance.o calls ray__child_query, defined in query/intersect.o: query is not below scene"
expect_fail "round a circle"

# A circle within one layer (scene.o and dynamic.o, before issue 26).
new_case layer-circle
obj scene/store 'int ray__live_prim(void); int ray__touch(void);
int ray__touch(void) { return ray__live_prim(); }'
obj scene/dynamic 'int ray__live_prim(void); int ray__touch(void);
int ray__live_prim(void) { return ray__touch(); }'
expect_fail "round a circle"

# A call beside, not below: image may not use prim.
new_case beside
obj prim/sphere 'int ray__sphere_t(void); int ray__sphere_t(void) { return 0; }'
obj image/png 'int ray__sphere_t(void); int ray__png(void);
int ray__png(void) { return ray__sphere_t(); }'
expect_fail "image/png.o calls ray__sphere_t, defined in prim/sphere.o: prim is not below image"

# An include above the layer, one without its layer, a file outside any.
new_case includes
obj core/vec 'int ray__v(void); int ray__v(void) { return 0; }'
mkdir -p "$t/src/query"
printf '%s\n' '/* x */' > "$t/src/query/query.h"
printf '%s\n' '#include "query/query.h"' >> "$t/src/core/vec.c"
expect_fail 'core/vec.c includes "query/query.h": query is not below core'
new_case bare-include
obj prim/plane 'int ray__p(void); int ray__p(void) { return 0; }'
printf '%s\n' '#include "prim.h"' >> "$t/src/prim/plane.c"
expect_fail 'prim/plane.c includes "prim.h": name its layer'
new_case stray
obj core/vec 'int ray__v(void); int ray__v(void) { return 0; }'
printf '%s\n' '/* x */' > "$t/src/stray.c"
expect_fail "src/stray.c is in no layer"
new_case big-room
obj core/vec 'int ray__v(void); int ray__v(void) { return 0; }'
i=0; while [ $i -lt 801 ]; do echo "/* line */"; i=$((i + 1)); done >> "$t/src/core/vec.c"
expect_fail "core/vec.c has 802 lines, more than 800"
new_case unknown-folder
obj misc/thing 'int ray__m(void); int ray__m(void) { return 0; }'
expect_fail "src/misc/ is not a layer"

# A platform header outside src/core/platform* (issue 28): <pthread.h>
# in the renderer, <windows.h> in a scene file, <png.h> beside png.c; the
# platform's own files may include them, ISO C's and intrinsics pass.
new_case platform-header
obj core/vec 'int ray__v(void); int ray__v(void) { return 0; }'
printf '%s\n' '#include <stdio.h>' '#include <emmintrin.h>' >> "$t/src/core/vec.c"
printf '%s\n' '#include <pthread.h>' '#include <windows.h>' > "$t/src/core/platform_x.c"
mkdir -p "$t/src/render" "$t/src/scene" "$t/src/image"
printf '%s\n' '#include <string.h>' '#include <pthread.h>' > "$t/src/render/render.c"
printf '%s\n' '#  include <windows.h>' > "$t/src/scene/store.c"
printf '%s\n' '#include <png.h>' > "$t/src/image/image.c"
expect_fail "render/render.c includes <pthread.h>: a platform header outside src/core/platform*"
expect_fail "scene/store.c includes <windows.h>"
expect_fail "image/image.c includes <png.h>"
if grep -q "core/\(vec\|platform_x\)" "$t/out"; then
    echo "test-check-layers: platform-header: ISO C's headers, intrinsics or the platform's own files refused:"
    cat "$t/out"
    exit 1
fi

# The real library passes, and fails with one more object that calls
# upward: a scene file calling the query layer's ray_intersect.
if [ $# -gt 0 ]; then
    SRCDIR=$root/src "$check" "$objdir" "$@" > "$tmp/real.out" 2>&1 || {
        echo "test-check-layers: the library's objects failed:"
        cat "$tmp/real.out"
        exit 1
    }
    new_case real-upward
    cp -R "$objdir/." "$t/obj/"
    real=$(for o in "$@"; do echo "$t/obj/${o#"$objdir"/}"; done)
    cp -R "$root/src/." "$t/src/"
    obj scene/upward 'struct ray_scene; int ray_intersect(const struct ray_scene *s,
const void *r, void *h, const void *q); int ray__up(const struct ray_scene *s);
int ray__up(const struct ray_scene *s) { return ray_intersect(s, 0, 0, 0); }'
    expect_fail "scene/upward.o calls ray_intersect, defined in query/intersect.o" \
        $real "$t/obj/scene/upward.o"
fi
echo "test-check-layers: check-layers.sh fails as it should in $((cases - 1)) cases, passes a clean tree${1:+ and the library}"
