// SPDX-License-Identifier: MIT
//
// whitted.pov -- examples/scenes.h whitted_scene() for POV-Ray 3.7, so
// that bench/whitted.c can time both renderers on the same work: the same
// objects, the same effects, the same ray-tree depth and weight cut.
//
// Coordinates: libray is right-handed, POV-Ray left-handed.  Every z is
// negated (a mirror in z), which keeps x to the right and y up in the
// image: libray's camera at (0, 1.5, 5.5) looking toward -z is POV's at
// <0, 1.5, -5.5> looking toward +z, and the image is the same way round.
//
// What matches exactly (from src/trace/materials.c, src/trace/light.c, src/prim/plane.c):
//   - camera: vertical field of view 45 degrees; POV's "angle" is the
//     horizontal one, 2 atan(tan(22.5 deg) * width / height).
//   - point light at (4, 7, 5), intensity 80, falling off as 1/d^2
//     (libray's light.c): POV's fade_power 2 attenuates by
//     2 / (1 + (d / fade_distance)^2) (Attenuate_Light, lightsource.cpp;
//     3.7.0 ignores a fade_distance of 0), which for fade_distance 0.01
//     and a colour of 80 / (2 * 0.01^2) is 80 / (d^2 + 0.01^2): 1/d^2 to a
//     relative 4e-6 at the nearest lit point (d >= 5, the light being at
//     height 7 and the spheres' tops at 2).
//   - floor: the plane y = 0, checker of scale 1; libray's plane (u, v)
//     for the normal +y is (x, -z) (vec.h ray__tangent_frame), so its
//     cell parity floor(u) + floor(v) is POV's floor(x) + floor(z) in the
//     mirrored coordinates; even cells red, odd yellow.  Blinn-Phong:
//     ambient * diffuse colour + (diffuse colour n.l + 0.2 (n.h)^40)
//     * light: POV's "ambient" (a colour, times ambient_light 1), "diffuse
//     1" of the pigment, "specular 0.2 roughness 1/40" (POV's specular is
//     Blinn's half-vector lobe, (n.h)^(1/roughness), in the light's
//     colour).  The ambient 0.12/0.12/0.14 is the scene's (libray
//     multiplies it by the diffuse colour, as POV multiplies its finish
//     ambient by the pigment).
//   - mirror sphere (-1.1, 1, -1.2), r 1: reflection 0.9, nothing else
//     (no diffuse, no highlight, so neither renderer casts shadow rays
//     from it).
//   - sky: the gradient of the escaping ray's direction, base + delta *
//     (y + 1) / 2 (examples/common.h sky_gradient): a sky_sphere gradient
//     over y in [-1, 1].
//   - depth: libray's default max_depth 8 counts bounces (the camera ray
//     is depth 0), so 9 levels; POV's max_trace_level counts levels (the
//     camera ray is level 1, trace.cpp TraceRay): 9.  adc_bailout 1/256 is
//     libray's default min_weight (RAY_DEFAULT_MIN_WEIGHT).
//   - gamma: assumed_gamma 1, so POV works in linear values as libray does.
//
// What POV cannot match exactly:
//   - glass sphere (0.9, 0.8, 0.6), r 0.8, ior 1.5: libray splits each hit
//     by the Fresnel reflectance F (reflection F, refraction 1 - F, total
//     internal reflection past the critical angle) and attenuates the light
//     that crossed the glass by exp(-absorption d).  POV: reflection
//     {0, 1 fresnel on} with conserve_energy (refraction weighted 1 - F),
//     and the interior's exponential fade (fade_power 1001: colour *
//     exp(-(1 - fade_color) d / fade_distance)), fade_distance 1 and
//     fade_color 1 - absorption.  POV fades only the refracted part at the
//     exit (trace.cpp), libray the whole colour leaving the inside ray;
//     the difference is the light reflected inside the glass, a few
//     percent of a few percent.
//   - shadows through the glass: libray's shadow rays stop at any surface
//     (the glass casts a black shadow); POV lets them through a
//     transparent pigment, filtered, so its shadow rays that meet the
//     glass go on to the light (a little more work for POV, a lighter
//     shadow in its image).
//   - sample positions: libray looks through pixel centres as POV does,
//     but the two differ in rounding and epsilons (POV's surface
//     tolerance), so the images agree to the eye, not bit for bit.

#version 3.7;

global_settings {
    assumed_gamma 1.0
    max_trace_level 9
    adc_bailout 1/256
    ambient_light rgb 1
}

camera {
    perspective
    location <0, 1.5, -5.5>
    look_at <0, 0.9, 0>
    up y
    right x * image_width / image_height
    angle 2 * degrees(atan(tan(radians(45 / 2)) * image_width / image_height))
    sky y
}

// 80 / (2 fade_distance^2): see the header on the fall-off.
light_source {
    <4, 7, -5>
    color rgb 80 / (2 * 0.01 * 0.01)
    fade_power 2
    fade_distance 0.01
}

sky_sphere {
    pigment {
        gradient y
        color_map {
            [0 color rgb <0.35, 0.45, 0.75>]
            [1 color rgb <0.60, 0.75, 0.95>]
        }
        scale 2
        translate -1 * y
    }
}

#declare Floor_Finish = finish {
    ambient rgb <0.12, 0.12, 0.14>
    diffuse 1
    specular 0.2
    roughness 1 / 40
    reflection 0
}

plane {
    y, 0
    pigment {
        checker
        color rgb <0.75, 0.08, 0.06>    // even cells: libray's "even"
        color rgb <0.8, 0.7, 0.1>       // odd cells
    }
    finish { Floor_Finish }
}

sphere {
    <-1.1, 1, 1.2>, 1
    texture {
        pigment { color rgb 0 }
        finish { ambient 0 diffuse 0 specular 0 reflection rgb 0.9 }
    }
}

sphere {
    <0.9, 0.8, -0.6>, 0.8
    texture {
        pigment { color rgbt <1, 1, 1, 1> }
        finish {
            ambient 0 diffuse 0 specular 0
            reflection { 0, 1 fresnel on }
            conserve_energy
        }
    }
    interior {
        ior 1.5
        fade_power 1001
        fade_distance 1
        fade_color rgb <0.95, 0.98, 0.99>
    }
}
