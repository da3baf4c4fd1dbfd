/* SPDX-License-Identifier: MIT */
/*
** controller.c -- a character controller on the shape queries: a
** capsule walks over the game example's terrain (examples/game.c) among
** its crates (instances of one 12-triangle mesh, standing on the ground
** here) and a few low ledges, with gravity, sliding along walls,
** stepping up onto ledges and jumping, driven by random inputs for
** 10,000 frames.  Each frame "collides and slides": ray_intersect_sweep
** moves the capsule to its first contact (conservative: never inside),
** the rest of the motion loses its part along the contact's normal and
** is swept again; a capsule that starts overlapping something is pushed
** out along the contact's normal by its depth.  Prints the frames, the
** contacts, the depenetrations, the ledges climbed and the lowest height the
** character's feet reached above the ground under them (a ray straight
** down onto the terrain), and exits 1 if they ever went below it.
**
** RAY_CONTROLLER_FRAMES sets the number of frames (default 10000).
*/
#include "common.h"
#include "terrain.h"

#define CRATES 200
#define LEDGES 24
#define TERRAIN_MASK 1u
#define SOLID_MASK 3u             /* terrain, crates, ledges, walls */

#define RADIUS 0.4                /* the capsule: feet at y - HALF - R */
#define HALF 0.5                  /* half the segment between its ends */
#define STEP 0.35                 /* the highest ledge it steps onto */
#define SKIN 1e-4                 /* kept between it and what it touches */
#define GRAVITY -9.81
#define DT (1.0 / 60)
#define SPEED 4.0
#define JUMP 5.0

/* The terrain (examples/terrain.h) as one mesh. */
static int add_terrain(ray_scene *s, unsigned *id)
{
    ray_mesh m;

    terrain_mesh(&m);
    return ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, id);
}

/* A box primitive from lo to hi, axis-aligned, solid. */
static int add_block(ray_scene *s, ray_vec3 lo, ray_vec3 hi)
{
    ray_box_params b;
    unsigned id;
    int rc;

    b.center = vec((lo.x + hi.x) / 2, (lo.y + hi.y) / 2, (lo.z + hi.z) / 2);
    b.half_extents = vec((hi.x - lo.x) / 2, (hi.y - lo.y) / 2,
                         (hi.z - lo.z) / 2);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    if ((rc = ray_scene_add_box(s, &b, RAY_NO_MATERIAL, &id)) != RAY_OK)
        return rc;
    return ray_scene_set_mask(s, id, 2u);
}

/* The world: terrain, 200 crates where game.c puts them but standing on
** the ground (turned as at its first frame), 24 ledges a step high,
** and walls round the terrain's edge. */
static ray_scene *build_world(ray_scene **crate)
{
    ray_scene *w;
    unsigned k, id;
    ray_transform t;

    check(ray_scene_new(crate, NULL, NULL), "ray_scene_new");
    check(example_add_box_mesh(*crate, vec(-0.4, 0, -0.4), vec(0.4, 0.8, 0.4),
                               RAY_NO_MATERIAL, NULL), "crate");
    check(ray_scene_commit(*crate), "crate commit");
    check(ray_scene_new(&w, NULL, NULL), "ray_scene_new");
    check(add_terrain(w, &id), "terrain");
    check(ray_scene_set_mask(w, id, TERRAIN_MASK), "terrain mask");
    for (k = 0; k < CRATES; k++) {
        double a = k, x = -22 + 2.2 * (k % 20) + 0.5 * cos(a);
        double z = -11 + 2.2 * (double)(k / 20) + 0.5 * sin(a);
        ray_transform_identity(&t);
        t.m[0][0] = cos(a), t.m[0][2] = sin(a);
        t.m[2][0] = -sin(a), t.m[2][2] = cos(a);
        t.m[0][3] = x, t.m[1][3] = terrain_height(x, z) - 0.1, t.m[2][3] = z;
        check(ray_scene_add_instance(w, *crate, &t, &id), "crate");
        check(ray_scene_set_mask(w, id, 2u), "crate mask");
    }
    for (k = 0; k < LEDGES; k++) {
        double x = -20 + 40.0 * (k % 6) / 5, z = 14 + 3.0 * (double)(k / 6);
        double y = terrain_height(x, z);
        check(add_block(w, vec(x - 1, y - 1, z - 1),
                        vec(x + 1, y + 0.3, z + 1)), "ledge");
    }
    check(add_block(w, vec(-30, -5, -30), vec(-23, 10, 30)), "wall");
    check(add_block(w, vec(23, -5, -30), vec(30, 10, 30)), "wall");
    check(add_block(w, vec(-30, -5, -30), vec(30, 10, -23)), "wall");
    check(add_block(w, vec(-30, -5, 23), vec(30, 10, 30)), "wall");
    check(ray_scene_commit(w), "commit");
    return w;
}

typedef struct body {
    ray_vec3 p;                   /* the capsule's centre */
    ray_vec3 v;                   /* its velocity */
    int grounded;
} body;

typedef struct tally {
    unsigned long contacts, depenetrations, steps, ledges;
    double lowest;                /* feet above the terrain, the least */
} tally;

/* The capsule at centre p, moved by "move" over [0, 1]. */
static void sweep_of(ray_vec3 p, ray_vec3 move, ray_sweep *s)
{
    /* Zero is the default: tmin 0, and tmax 0 sweeps the whole move. */
    ray_sweep whole = {.shape = {.a = vec(p.x, p.y - HALF, p.z),
                                 .b = vec(p.x, p.y + HALF, p.z),
                                 .radius = RADIUS},
                       .dir = move};

    *s = whole;
}

static double dot(ray_vec3 a, ray_vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static ray_vec3 add(ray_vec3 a, ray_vec3 b, double s)
{
    return vec(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z);
}

static ray_vec3 cross(ray_vec3 a, ray_vec3 b)
{
    return vec(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z,
               a.x * b.y - a.y * b.x);
}

/*
** The motion m with its parts into the planes touched so far taken off
** (Quake's slide move): along one plane; into two, along the crease
** between them; into three, none.
*/
static ray_vec3 clip(ray_vec3 m, const ray_vec3 *planes, int n)
{
    int i, j;

    for (i = 0; i < n; i++) {
        ray_vec3 c;
        if (dot(m, planes[i]) >= 0)
            continue;
        c = add(m, planes[i], -dot(m, planes[i]));
        for (j = 0; j < n; j++)
            if (j != i && dot(c, planes[j]) < 0)
                break;
        if (j == n)
            return c;                    /* along plane i, into none */
        for (j = 0; j < n; j++) {
            ray_vec3 crease;
            double len;
            if (j == i)
                continue;
            crease = cross(planes[i], planes[j]);
            len = sqrt(dot(crease, crease));
            if (!(len > 1e-12))
                continue;
            crease = vec(crease.x / len, crease.y / len, crease.z / len);
            c = vec(crease.x * dot(m, crease), crease.y * dot(m, crease),
                    crease.z * dot(m, crease));
            if (n < 3 || dot(c, planes[3 - i - j]) >= 0)
                return c;                /* along the crease */
        }
        return vec(0, 0, 0);             /* a corner of three: stop */
    }
    return m;
}

/*
** Collide and slide: up to 4 sweeps, each moving to SKIN short of the
** first contact along the path (clear: the sweep is conservative), the
** rest of the motion losing its
** parts into the planes met (clip).  An overlap at the start pushes the
** capsule out by its depth.  *floor: the largest normal's y met (0:
** none); *wall: the least (1: none).
*/
static void slide(const ray_scene *w, body *b, ray_vec3 move, tally *tl,
                  double *floor, double *wall)
{
    ray_vec3 planes[4];
    int iter, np = 0;

    *floor = 0;
    *wall = 1;
    for (iter = 0; iter < 4; iter++) {
        ray_sweep s;
        ray_contact c;
        int rc;
        if (dot(move, move) < 1e-18)
            break;
        sweep_of(b->p, move, &s);
        rc = ray_intersect_sweep(w, &s, NULL, &c);
        if (rc < 0) {
            fprintf(stderr, "controller: %s\n", ray_strerror(-rc));
            exit(1);
        }
        if (rc == 0) {
            b->p = add(b->p, move, 1);
            break;
        }
        tl->contacts++;
        if (c.flags & RAY_CONTACT_OVERLAP) {
            b->p = add(b->p, c.n, c.depth + SKIN);
            tl->depenetrations++;
        } else {
            /* Stop SKIN short of the contact along the path, which the
            ** sweep found clear: never into anything else. */
            double len = sqrt(dot(move, move));
            double t = c.t - SKIN / len > 0 ? c.t - SKIN / len : 0;
            b->p = add(b->p, move, t);
            move = vec(move.x * (1 - t), move.y * (1 - t), move.z * (1 - t));
        }
        if (np < 4)
            planes[np++] = c.n;
        move = clip(move, planes, np < 3 ? np : 3);
        *floor = c.n.y > *floor ? c.n.y : *floor;
        *wall = c.n.y < *wall ? c.n.y : *wall;
        if (c.n.y > 0.7 && b->v.y < 0)
            b->v.y = 0;
    }
}

/* Is the capsule at p clear of everything (no overlap)? */
static int clear_at(const ray_scene *w, ray_vec3 p)
{
    /* The capsule itself (kind 0, RAY_SHAPE_CAPSULE: the default). */
    ray_shape cap = {.a = vec(p.x, p.y - HALF, p.z),
                     .b = vec(p.x, p.y + HALF, p.z), .radius = RADIUS};
    size_t n;

    return ray_overlap_shape_all(w, &cap, NULL, NULL, 0, &n) == 0;
}

/*
** A horizontal move blocked by something no higher than STEP: lift the
** capsule by STEP, move, settle back down onto walkable ground; kept
** only if it ends higher than the plain slide would and clear.
*/
static int step_up(const ray_scene *w, body *b, ray_vec3 move, double plain,
                   tally *tl)
{
    body t = *b;
    tally scratch = *tl;
    ray_sweep s;
    ray_contact c;

    double floor, wall;

    slide(w, &t, vec(0, STEP, 0), &scratch, &floor, &wall);
    slide(w, &t, vec(move.x, 0, move.z), &scratch, &floor, &wall);
    sweep_of(t.p, vec(0, -2 * STEP, 0), &s);
    if (ray_intersect_sweep(w, &s, NULL, &c) != 1 || c.n.y < 0.7 ||
        (c.flags & RAY_CONTACT_OVERLAP))
        return 0;
    t.p = add(t.p, s.dir, c.t - SKIN / (2 * STEP) > 0 ? c.t - SKIN / (2 * STEP)
                                                       : 0);
    /* Worth it: higher, farther along than the plain slide got, clear. */
    if (t.p.y <= b->p.y + 0.05 ||
        dot(vec(t.p.x - b->p.x, 0, t.p.z - b->p.z), move) <= plain ||
        !clear_at(w, t.p))
        return 0;
    b->p = t.p;
    b->v.y = 0;
    tl->contacts = scratch.contacts;
    tl->steps++;
    return 1;
}

/* The feet's height above the terrain under them (a ray straight down
** onto the terrain alone, mask TERRAIN_MASK). */
static double feet_clearance(const ray_scene *w, ray_vec3 p)
{
    ray_query q;
    ray_ray r;
    ray_hit h;

    q = (ray_query){.ignore_mask = ~TERRAIN_MASK};  /* the terrain alone */
    r.org = vec(p.x, 100, p.z);
    r.dir = vec(0, -1, 0);
    r.tmin = 0;
    r.tmax = HUGE_VAL;
    if (ray_intersect(w, &r, &h, &q) != 1)
        return HUGE_VAL;             /* off the terrain: nothing under */
    return (p.y - HALF - RADIUS) - h.p.y;
}

int main(int argc, char **argv)
{
    const char *env = getenv("RAY_CONTROLLER_FRAMES");
    unsigned long frames = env != NULL ? strtoul(env, NULL, 10) : 10000, f;
    ray_scene *world, *crate;
    body b;
    tally tl = {0, 0, 0, 0, HUGE_VAL};
    int on_ledge = 0;
    unsigned rng = 12345;
    double heading = 0;

    if (example_no_arguments(argc, argv, "controller",
                             "A capsule character walks over the game's "
                             "terrain among crates and ledges, by sweeps.\n"
                             "Environment: RAY_CONTROLLER_FRAMES (default "
                             "10000).") != 0)
        return 2;
    if (frames == 0 || frames > 10000000)
        frames = 10000;
    world = build_world(&crate);
    b.p = vec(0.5, terrain_height(0.5, 8) + HALF + RADIUS + 0.5, 8);
    b.v = vec(0, 0, 0);
    b.grounded = 0;
    for (f = 0; f < frames; f++) {
        ray_vec3 want, move;
        double floor_y, wall_y, c;
        /* Random inputs: a new heading now and then, a jump sometimes. */
        rng = rng * 1664525u + 1013904223u;
        if ((rng >> 24) % 90 == 0)
            heading = 6.283185307179586 * (double)(rng >> 8 & 0xffff) / 65536;
        want = vec(SPEED * cos(heading), 0, SPEED * sin(heading));
        if (b.grounded && (rng >> 16) % 240 == 0)
            b.v.y = JUMP;
        b.v.y += GRAVITY * DT;
        b.v.x = want.x;
        b.v.z = want.z;
        /* Horizontal first (stepping up where a low ledge blocks it),
        ** then vertical, each collided and slid. */
        move = vec(b.v.x * DT, 0, b.v.z * DT);
        {
            body before = b;
            tally t0 = tl;
            slide(world, &b, move, &tl, &floor_y, &wall_y);
            if (b.grounded && wall_y < 0.7) {
                body stepped = before;
                tally t1 = t0;
                double plain = dot(vec(b.p.x - before.p.x, 0,
                                       b.p.z - before.p.z), move);
                if (step_up(world, &stepped, move, plain, &t1)) {
                    b = stepped;
                    tl = t1;
                }
            }
        }
        slide(world, &b, vec(0, b.v.y * DT, 0), &tl, &floor_y, &wall_y);
        /* Grounded: something walkable under the feet (a short probe). */
        if (floor_y > 0.7)
            b.grounded = 1;
        else {
            ray_sweep s;
            ray_contact cn;
            sweep_of(b.p, vec(0, -0.05, 0), &s);
            b.grounded = ray_intersect_sweep(world, &s, NULL, &cn) == 1 &&
                         cn.n.y > 0.7;
        }
        c = feet_clearance(world, b.p);
        if (c < tl.lowest)
            tl.lowest = c;
        /* Standing a ledge's height above the terrain: on a ledge (the
        ** crates are higher than a step). */
        if (b.grounded && c > 0.15 && c < 0.65) {
            tl.ledges += !on_ledge;
            on_ledge = 1;
        } else if (b.grounded)
            on_ledge = 0;
    }
    printf("%lu frames: %lu contacts, %lu depenetrations, %lu ledges "
           "climbed (%lu by a step up, the others by the capsule's round "
           "foot); lowest height of the feet above the ground %.6g m\n",
           frames, tl.contacts, tl.depenetrations, tl.ledges, tl.steps,
           tl.lowest);
    ray_scene_free(world);
    ray_scene_free(crate);
    /* Below the ground by more than the skin's rounding: fell through. */
    if (tl.lowest < -1e-9) {
        fprintf(stderr, "controller: the character fell through the floor "
                "(%.17g below it)\n", -tl.lowest);
        return 1;
    }
    return 0;
}
