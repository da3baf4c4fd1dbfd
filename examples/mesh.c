/*
** mesh.c -- load a Wavefront OBJ and render it: a grey Blinn-Phong
** surface (smooth if the file has normals) on a floor, under a spherical
** light, seen from the +z side at a distance that frames the model.
**
**     mesh model.obj [out.png [width height [samples [threads]]]]
**
** scripts/fetch-bunny.sh writes data/bunny.obj (and finer versions).
*/
#include "obj.h"
#include "common.h"

int main(int argc, char **argv)
{
    static const ray_phong_params clay = {{0.7, 0.66, 0.6}, {0.25, 0.25, 0.25},
                                          30, 1, {0, 0, 0}};
    static const ray_phong_params ground = {{0.35, 0.4, 0.45}, {0, 0, 0}, 1,
                                            0, {0, 0, 0}};
    ray_vec3 lo, hi, centre;
    obj_mesh obj;
    ray_mesh mesh;
    ray_material m;
    ray_light lamp;
    ray_camera cam;
    ray_scene *scene;
    unsigned m_clay, m_ground;
    double diag;
    char err[600];
    size_t i;
    int rc;

    if (argc < 2) {
        fprintf(stderr, "usage: mesh model.obj [out.png [width height "
                        "[samples [threads]]]]\n");
        return 2;
    }
    if (obj_load(argv[1], &obj, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        return 1;
    }
    lo = hi = obj.vertices[0];
    for (i = 1; i < obj.vertex_count; i++) {
        ray_vec3 v = obj.vertices[i];
        lo = vec(fmin(lo.x, v.x), fmin(lo.y, v.y), fmin(lo.z, v.z));
        hi = vec(fmax(hi.x, v.x), fmax(hi.y, v.y), fmax(hi.z, v.z));
    }
    centre = vec((lo.x + hi.x) / 2, (lo.y + hi.y) / 2, (lo.z + hi.z) / 2);
    diag = sqrt((hi.x - lo.x) * (hi.x - lo.x) + (hi.y - lo.y) * (hi.y - lo.y) +
                (hi.z - lo.z) * (hi.z - lo.z));
    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    m = ray_material_phong(&clay);
    check(ray_scene_add_material(scene, &m, &m_clay), "material");
    m = ray_material_phong(&ground);
    check(ray_scene_add_material(scene, &m, &m_ground), "material");
    mesh = obj_as_ray_mesh(&obj);
    check(ray_scene_add_mesh(scene, &mesh, m_clay, NULL), "ray_scene_add_mesh");
    check(ray_scene_add_plane(scene, vec(0, lo.y, 0), vec(0, 1, 0), m_ground,
                              NULL), "floor");
    memset(&lamp, 0, sizeof lamp);
    lamp.kind = RAY_LIGHT_SPHERE;
    lamp.position = vec(centre.x + diag, hi.y + diag, centre.z + diag);
    lamp.radius = 0.15 * diag;
    lamp.intensity = rgb(2.2 * diag * diag, 2.2 * diag * diag, 2.2 * diag * diag);
    lamp.samples = 9;
    check(ray_scene_add_light(scene, &lamp, NULL), "light");
    check(ray_scene_set_ambient(scene, rgb(0.15, 0.15, 0.17)), "ambient");
    check(ray_scene_set_background(scene, rgb(0.55, 0.65, 0.8)), "background");
    check(ray_scene_commit(scene), "ray_scene_commit");
    memset(&cam, 0, sizeof cam);
    cam.position = vec(centre.x, centre.y + 0.25 * diag, centre.z + 1.3 * diag);
    cam.look_at = centre;
    cam.up = vec(0, 1, 0);
    cam.vfov = 40;
    printf("mesh: %s: %zu triangles, %zu vertices%s%s\n", argv[1],
           obj.triangle_count, obj.vertex_count,
           obj.normals ? ", normals" : "", obj.texcoords ? ", texcoords" : "");
    obj_free(&obj);
    rc = render_to_png("mesh", scene, &cam, argc - 1, argv + 1, 480, 360);
    ray_scene_free(scene);
    return rc;
}
