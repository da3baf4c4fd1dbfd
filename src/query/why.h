/* SPDX-License-Identifier: MIT */
/*
** why.h -- a refused query's reason, in words, for the caller's buffer
** (ray_query.why, ray_batch.why, ray_contains_options.why; ray.h, "Why a
** query refused").  Called on the refusal path only, after a query's own
** checks have failed, so that a query that answers pays nothing for it:
** the reason is found again by walking the same checks in their order.
*/
#ifndef RAY_QUERY_WHY_H
#define RAY_QUERY_WHY_H

#include "scene/scene.h"

/* A vector as the reasons print it: every digit a double has, so that
** the value named is the value given. */
#define RAY__WHY_V3 "(%.17g, %.17g, %.17g)"
#define RAY__WHY_V3ARGS(v) (v).x, (v).y, (v).z

/* Write "op: " and the formatted reason into why[size] (nothing when why
** is NULL or size 0; cut to fit, always terminated) and return rc. */
int ray__why(char *why, size_t size, int rc, const char *op,
             const char *fmt, ...) RAY__PRINTF(5, 6);

/* A scene's RAY_ESTATE in words: not committed (never, or changed since),
** else an instance met whose scene changed since s's commit. */
int ray__why_state(char *why, size_t size, int rc, const char *op,
                   const ray_scene *s);

#endif
