/* SPDX-License-Identifier: MIT */
/*
** picking.c -- ray queries without rendering, as a game uses them: a
** ground, a wall and three units as triangle meshes in one committed
** scene; then mouse picks (ray_intersect: what is under the cursor, and
** where) and line-of-sight checks (ray_occluded) answered by four threads
** at once, with no lock: nothing changes a committed scene while it is
** queried (ray(7), "Dynamic scenes").  Prints each
** answer in a fixed order, so the output is the same bytes on every run,
** and exits 1 if an answer is not the one the geometry implies.
*/
#include <pthread.h>

#include "common.h"

#define UNITS 3
#define GEOMETRIES (2 + UNITS)   /* ground, wall, units: ids 0, 1, 2... */
#define THREADS 4

/* Where each unit, a 1 x 2 x 1 box, stands on the ground (y = 0). */
static const ray_vec3 unit_base[UNITS] = {{-4, 0, 0}, {0.75, 0, 3},
                                         {5, 0, -2}};
/* The eyes of the line-of-sight checks: above each box's top (y = 2), so
** that a segment between two eyes starts and ends outside every box. */
#define EYE_HEIGHT 2.5
/* The mouse ray's origin: the game camera, above and in front. */
static const ray_vec3 camera = {0, 12, 14};

/* A query and its answer; each thread writes only its own queries. */
typedef struct query {
    const char *what;        /* printed label */
    ray_ray ray;
    int line_of_sight;       /* 1: ray_occluded, 0: ray_intersect */
    const char *expected;    /* name of what it must hit, or "clear" */
    int answer;              /* what the query returned */
    ray_hit hit;
} query;

typedef struct batch {
    const ray_scene *scene;
    query *queries;
    unsigned count, first;   /* this thread answers first, first + THREADS... */
} batch;

static ray_vec3 sub(ray_vec3 a, ray_vec3 b)
{
    return vec(a.x - b.x, a.y - b.y, a.z - b.z);
}

/* Two triangles a b c, a c d (the corners in order round the quad). */
static int add_quad(ray_scene *scene, const ray_vec3 corner[4],
                    unsigned material, unsigned *id)
{
    static const unsigned indices[6] = {0, 1, 2, 0, 2, 3};
    ray_mesh m;

    memset(&m, 0, sizeof m);
    m.vertices = corner;
    m.vertex_count = 4;
    m.indices = indices;
    m.triangle_count = 2;
    return ray_scene_add_mesh(scene, &m, material, id);
}

/* A unit: a 1 x 2 x 1 box of 12 triangles standing on "base". */
static int add_unit(ray_scene *scene, ray_vec3 base, unsigned material,
                    unsigned *id)
{
    return example_add_box_mesh(scene, vec(base.x - 0.5, base.y, base.z - 0.5),
                                vec(base.x + 0.5, base.y + 2, base.z + 0.5),
                                material, id);
}

static void *answer_batch(void *arg)
{
    const batch *b = arg;
    unsigned i;

    for (i = b->first; i < b->count; i += THREADS) {
        query *q = &b->queries[i];

        q->answer = q->line_of_sight ? ray_occluded(b->scene, &q->ray, NULL)
                                     : ray_intersect(b->scene, &q->ray,
                                                     &q->hit, NULL);
    }
    return NULL;
}

/* A mouse pick: the ray from the camera through a point of the world,
** its direction of unit length so that t is the distance. */
static query pick(const char *what, ray_vec3 toward, const char *expected)
{
    ray_vec3 d = sub(toward, camera);
    double length = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    query q;

    memset(&q, 0, sizeof q);
    q.what = what;
    q.ray.org = camera;
    q.ray.dir = vec(d.x / length, d.y / length, d.z / length);
    q.ray.tmin = 0;
    q.ray.tmax = HUGE_VAL;
    q.expected = expected;
    return q;
}

/* Can unit a see unit b: anything on the open segment between the eyes? */
static query sight(const char *what, unsigned a, unsigned b,
                   const char *expected)
{
    ray_vec3 eye_a = vec(unit_base[a].x, EYE_HEIGHT, unit_base[a].z);
    ray_vec3 eye_b = vec(unit_base[b].x, EYE_HEIGHT, unit_base[b].z);
    query q;

    memset(&q, 0, sizeof q);
    q.what = what;
    q.ray.org = eye_a;
    q.ray.dir = sub(eye_b, eye_a);
    q.ray.tmin = 0;
    q.ray.tmax = 1;                  /* t = 1 is eye b, not included */
    q.line_of_sight = 1;
    q.expected = expected;
    return q;
}

int main(int argc, char **argv)
{
    static const ray_vec3 ground[4] = {{-10, 0, -10}, {-10, 0, 10},
                                       {10, 0, 10}, {10, 0, -10}};
    static const ray_vec3 wall[4] = {{2, 0, -4}, {2, 3, -4}, {2, 3, 4},
                                     {2, 0, 4}};
    static ray_phong_params grey;    /* queries never shade: a material
                                        for rendering the same scene */
    const char *names[GEOMETRIES] = {0};     /* by geom_id */
    static const char *unit_names[UNITS] = {"unit 0", "unit 1", "unit 2"};
    query q[8];
    batch b[THREADS];
    pthread_t thread[THREADS];
    ray_material m;
    ray_scene *scene;
    unsigned mat, id, i, n = 0, wrong = 0;

    /* The examples' conventions (examples/common.h): -h and --help print
    ** the usage on stdout and exit 0, anything else is refused: 2. */
    if (example_no_arguments(argc, argv, "picking",
                             "Picks with mouse rays and checks lines of "
                             "sight on a small scene, from 4 threads; exits "
                             "1 if an answer is wrong.") != 0)
        return 2;
    ray_phong_params_init(&grey);
    m = ray_material_phong(&grey);
    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    check(ray_scene_add_material(scene, &m, &mat), "add_material");
    check(add_quad(scene, ground, mat, &id), "ground");
    names[id] = "ground";
    check(add_quad(scene, wall, mat, &id), "wall");
    names[id] = "wall";
    for (i = 0; i < UNITS; i++) {
        check(add_unit(scene, unit_base[i], mat, &id), unit_names[i]);
        names[id] = unit_names[i];
    }
    check(ray_scene_commit(scene), "commit");  /* unchanged while queried */

    q[n++] = pick("cursor on unit 0", vec(-4, 1, 0), "unit 0");
    q[n++] = pick("cursor on unit 1", vec(0.75, 1, 3), "unit 1");
    q[n++] = pick("cursor on unit 2", vec(5, 1, -2), "unit 2");
    q[n++] = pick("cursor on the wall", vec(2, 1.5, -1.25), "wall");
    q[n++] = pick("cursor on open ground", vec(-6, 0, 6), "ground");
    q[n++] = sight("unit 0 sees unit 1", 0, 1, "clear");
    q[n++] = sight("unit 0 sees unit 2", 0, 2, "blocked");
    q[n++] = sight("unit 1 sees unit 2", 1, 2, "blocked");

    for (i = 0; i < THREADS; i++) {
        b[i].scene = scene;
        b[i].queries = q;
        b[i].count = n;
        b[i].first = i;
        if (pthread_create(&thread[i], NULL, answer_batch, &b[i]) != 0) {
            fprintf(stderr, "picking: cannot start a thread\n");
            return 1;
        }
    }
    for (i = 0; i < THREADS; i++)
        pthread_join(thread[i], NULL);

    for (i = 0; i < n; i++) {
        const char *got;

        if (q[i].answer < 0) {                       /* misuse, not a miss */
            fprintf(stderr, "picking: %s: %s\n", q[i].what,
                    ray_strerror(q[i].answer));
            return 1;
        }
        if (q[i].line_of_sight) {
            got = q[i].answer ? "blocked" : "clear";
            printf("picking: %-22s %s\n", q[i].what, got);
        } else {
            got = q[i].answer == 0 ? "nothing"
                  : q[i].hit.geom_id < GEOMETRIES ? names[q[i].hit.geom_id]
                  : "?";
            printf("picking: %-22s %s", q[i].what, got);
            if (q[i].answer)
                printf(", triangle %u, distance %.3f, at (%.3f, %.3f, %.3f)",
                       q[i].hit.prim_id, q[i].hit.t, q[i].hit.p.x,
                       q[i].hit.p.y, q[i].hit.p.z);
            putchar('\n');
        }
        if (strcmp(got, q[i].expected) != 0) {
            fprintf(stderr, "picking: %s: expected %s\n", q[i].what,
                    q[i].expected);
            wrong++;
        }
    }
    printf("picking: %u queries on %u threads, %u wrong\n", n, THREADS, wrong);
    ray_scene_free(scene);
    return wrong == 0 ? 0 : 1;
}
