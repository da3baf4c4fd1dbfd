/* SPDX-License-Identifier: MIT */
/*
** game.c -- a headless game loop, no rendering: a static level (a
** 4,608-triangle terrain) and 200 moving objects, instances of two small
** meshes.  Every frame moves every object (ray_scene_set_transform) and
** commits (the top level is rebuilt, the meshes are not), then two
** threads answer picking rays (what is under the cursor: ray_intersect
** with a mask that skips the level) and line-of-sight checks between
** objects (ray_occluded with options, whose filter ignores the shooter
** itself).
** Prints the commit time per frame and the queries per second, and exits
** 1 if a pick straight down onto an object does not name that object.
**
** RAY_GAME_FRAMES sets the number of frames (default 60).
*/
#include <pthread.h>

#include "common.h"
#include "terrain.h"

#define OBJECTS 200
#define THREADS 2
#define QUERIES 4000          /* per thread and frame: half picks, half LOS */
#define LEVEL_MASK 1u
#define OBJECT_MASK 2u

/* The terrain (examples/terrain.h) as one mesh. */
static int add_terrain(ray_scene *s)
{
    ray_mesh m;

    terrain_mesh(&m);
    return ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL);
}

/* A crate: the box [-0.4, 0.4] x [0, 0.8] x [-0.4, 0.4], 12 triangles. */
static int add_crate(ray_scene *s, unsigned *id)
{
    return example_add_box_mesh(s, vec(-0.4, 0, -0.4), vec(0.4, 0.8, 0.4),
                                RAY_NO_MATERIAL, id);
}

/* Ignore the shooter: query_ud points at the instance id to skip. */
static int not_shooter(void *ud, const ray_ray *r, const ray_hit *c, void *q)
{
    (void)ud;
    (void)r;
    return q == NULL || c->inst_id != *(const unsigned *)q;
}

/* Object k's place at frame f: a slot of a 20 x 10 grid (2.2 apart),
** circling within it, turning, standing on the terrain. */
static ray_vec3 object_at(unsigned k, unsigned f)
{
    double a = 0.05 * f + k, x = -22 + 2.2 * (k % 20) + 0.5 * cos(a);
    double z = -11 + 2.2 * (double)(k / 20) + 0.5 * sin(a);
    return vec(x, terrain_height(x, z) + 1.2, z);
}

static void object_xfm(unsigned k, unsigned f, ray_transform *t)
{
    ray_vec3 p = object_at(k, f);
    double a = 0.1 * f + k, c = cos(a), s = sin(a);

    ray_transform_identity(t);
    t->m[0][0] = c;
    t->m[0][2] = s;
    t->m[2][0] = -s;
    t->m[2][2] = c;
    t->m[0][3] = p.x;
    t->m[1][3] = p.y;
    t->m[2][3] = p.z;
}

typedef struct worker {
    const ray_scene *scene;
    unsigned *ids;            /* the objects' instance ids */
    unsigned frame, seed;
    unsigned long long picks, sights, blocked, wrong;
} worker;

/* Half picks straight down onto an object (which must be named), half
** lines of sight between two objects' centres, ignoring the shooter. */
static void *work(void *arg)
{
    worker *w = arg;
    unsigned i, rng = w->seed;
    /* Zero is the default: los ignores nothing; pick ignores every mask
    ** bit but the objects', so the level is not pickable. */
    ray_query pick = {.ignore_mask = ~OBJECT_MASK}, los = {0};

    for (i = 0; i < QUERIES; i++) {
        unsigned a, b;
        rng = rng * 1664525u + 1013904223u;
        a = (rng >> 8) % OBJECTS;
        rng = rng * 1664525u + 1013904223u;
        b = (rng >> 8) % OBJECTS;
        if (i % 2 == 0) {
            ray_vec3 p = object_at(a, w->frame);
            ray_ray r;
            ray_hit h;
            r.org = vec(p.x, 50, p.z);
            r.dir = vec(0, -1, 0);
            r.tmin = 0;
            r.tmax = HUGE_VAL;
            if (ray_intersect(w->scene, &r, &h, &pick) != 1 ||
                h.inst_id != w->ids[a])
                w->wrong++;
            w->picks++;
        } else {
            ray_vec3 p = object_at(a, w->frame), q = object_at(b, w->frame);
            ray_ray r;
            int rc;
            r.org = p;
            r.dir = vec(q.x - p.x, q.y - p.y, q.z - p.z);
            r.tmin = 0;
            r.tmax = 0.75;          /* short of the target's own crate */
            los.query_ud = &w->ids[a];
            rc = ray_occluded(w->scene, &r, &los);
            if (rc < 0)
                w->wrong++;
            w->blocked += rc == 1;
            w->sights++;
        }
    }
    return NULL;
}

static int median_cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    const char *env = getenv("RAY_GAME_FRAMES");
    unsigned frames = env != NULL ? (unsigned)atoi(env) : 60, f, k, i;
    ray_scene *world, *crate;
    unsigned ids[OBJECTS], crate_mesh;
    double *commit_s, query_s = 0, t;
    unsigned long long picks = 0, sights = 0, blocked = 0, wrong = 0;
    ray_transform xf;

    if (example_no_arguments(argc, argv, "game",
                             "A headless game loop: 200 moving instances "
                             "over a terrain, committed every frame, queried "
                             "from 2 threads.\nEnvironment: RAY_GAME_FRAMES "
                             "(default 60).") != 0)
        return 2;
    if (frames == 0 || frames > 100000)
        frames = 60;
    commit_s = malloc(frames * sizeof *commit_s);
    if (commit_s == NULL)
        return 1;
    /* The object: one crate mesh, shared by every instance; its filter
    ** lets line-of-sight rays pass through the shooter's own crate. */
    check(ray_scene_new(&crate, NULL, NULL), "ray_scene_new");
    check(add_crate(crate, &crate_mesh), "crate");
    check(ray_scene_set_filter(crate, crate_mesh, not_shooter, NULL,
                               RAY_FILTER_OCCLUDED), "filter");
    check(ray_scene_commit(crate), "crate commit");
    check(ray_scene_new(&world, NULL, NULL), "ray_scene_new");
    check(add_terrain(world), "terrain");
    check(ray_scene_set_mask(world, 0, LEVEL_MASK), "terrain mask");
    for (k = 0; k < OBJECTS; k++) {
        object_xfm(k, 0, &xf);
        check(ray_scene_add_instance(world, crate, &xf, &ids[k]), "object");
        check(ray_scene_set_mask(world, ids[k], OBJECT_MASK), "object mask");
    }
    check(ray_scene_commit(world), "commit");
    for (f = 1; f <= frames; f++) {
        pthread_t th[THREADS];
        worker w[THREADS];
        t = now_seconds();
        for (k = 0; k < OBJECTS; k++) {
            object_xfm(k, f, &xf);
            check(ray_scene_set_transform(world, ids[k], &xf), "move");
        }
        check(ray_scene_commit(world), "frame commit");
        commit_s[f - 1] = now_seconds() - t;
        t = now_seconds();
        for (i = 0; i < THREADS; i++) {
            w[i].scene = world;
            w[i].ids = ids;
            w[i].frame = f;
            w[i].seed = 7919u * f + i;
            w[i].picks = w[i].sights = w[i].blocked = w[i].wrong = 0;
            if (pthread_create(&th[i], NULL, work, &w[i]) != 0) {
                fprintf(stderr, "game: cannot start a thread\n");
                return 1;
            }
        }
        for (i = 0; i < THREADS; i++) {
            pthread_join(th[i], NULL);
            picks += w[i].picks;
            sights += w[i].sights;
            blocked += w[i].blocked;
            wrong += w[i].wrong;
        }
        query_s += now_seconds() - t;
    }
    qsort(commit_s, frames, sizeof *commit_s, median_cmp);
    printf("%u frames, %d objects (instances of a %u-triangle crate) over "
           "a %d-triangle terrain\n", frames, OBJECTS, 12u,
           2 * TERRAIN_GRID * TERRAIN_GRID);
    printf("commit per frame: median %.3f ms, worst %.3f ms\n",
           1e3 * commit_s[frames / 2], 1e3 * commit_s[frames - 1]);
    printf("queries: %llu picks, %llu lines of sight (%llu blocked) from %d "
           "threads: %.2f million per second\n", picks, sights, blocked,
           THREADS, (double)(picks + sights) / query_s / 1e6);
    free(commit_s);
    ray_scene_free(world);
    ray_scene_free(crate);
    if (wrong > 0) {
        fprintf(stderr, "game: %llu queries answered wrongly\n", wrong);
        return 1;
    }
    return 0;
}
