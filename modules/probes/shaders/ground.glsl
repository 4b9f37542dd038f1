// Planar probes' grounds in a shader (probe.h, PlanarGround; modules/probes/planar.cpp renders
// them): a ray that meets a planar probe's plane from above, inside its rectangle and no farther
// than the local probes' proxy, reads the plane as the ground's orthographic view saw it. A
// cube's proxy places that floor wrong wherever an object standing on it hides it from the
// capture point: the underside of a sphere on a mirror floor showed the far wall (issue 24).
// Readers: probes.capture_bounce (probe faces, CMO faces, planar images) and the reflections
// module's probe step (chain.glsl). Before including, define GROUND_BUFFER_BINDING and
// GROUND_IMAGES_BINDING (set 0).
#ifndef SPECULUM_GROUND_GLSL
#define SPECULUM_GROUND_GLSL

#include "common/brdf.glsl"  // coneTan
#include "probes/shaders/probe.h"

layout(set = 0, binding = GROUND_BUFFER_BINDING, std430) readonly buffer GroundBuffer {
    PlanarGround grounds[];
};
layout(set = 0, binding = GROUND_IMAGES_BINDING) uniform sampler2DArray groundImages;  // trilinear clamp

// The ground texel that ray p + t r meets from above, at most `limit` away, at its cone's
// footprint, with the plane's normal and the ray's t there: rgb premultiplied by the coverage in
// a (0: no ground there), or a metal's marker (a <= -1: ground_store.comp; capture_bounce's
// metalGround reflects the ray there).
vec4 groundTexel(uint count, vec3 p, vec3 r, float roughness, float limit, out vec3 planeNormal, out float tHit) {
    planeNormal = vec3(0.0, 1.0, 0.0);
    tHit = 0.0;
    for (uint i = 0u; i < count; ++i) {
        PlanarGround g = grounds[i];
        float above = dot(g.plane.xyz, p) + g.plane.w, toward = -dot(g.plane.xyz, r);
        if (above <= 0.0 || toward <= 0.0 || above > limit * toward) continue;
        float t = above / toward;
        planeNormal = g.plane.xyz;
        tHit = t;
        vec4 c = g.viewProj * vec4(p + r * t, 1.0);
        vec2 uv = c.xy / c.w * 0.5 + 0.5;
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) continue;
        float lod = clamp(log2(max(2.0 * coneTan(roughness) * t / g.params.y, 1.0)), 0.0, g.params.z);
        // Seen from straight above, less its direct specular (ground_store.comp): a grazing ray
        // sees more of what the plane reflects, but fading the ground out from cos 0.35 to 0.15
        // (where a dielectric's Fresnel passes 0.1) lost 0.21 dB on gallery.main and gained at
        // most 0.03 elsewhere: it reads the plane at every angle.
        return textureLod(groundImages, vec3(uv, g.params.x), lod);
    }
    return vec4(0.0);
}

// How far a ground may lie along the ray: no farther than the probes' proxy (a box's floor on
// the plane meets the ray at the same t, a wall first hides it), with 2 cm of slack for the two
// intersections' rounding; with no probe at p (proxyDistance 0), anywhere.
float groundLimit(float proxyDistance) {
    return proxyDistance > 0.0 ? proxyDistance + 0.02 : 1e30;
}

// Narrow lobes only, as the planar image (planarShare): all up to roughness 0.2, none from 0.3.
// One lookup at the mirror ray's point stands in for a lobe only while the lobe is narrow;
// serving every roughness cost gallery.main's rough band 1.3 dB (19.20 -> 17.88), where the
// walls' wide lobes take the floor's average for the whole hemisphere. Up to 0.5 scored the same
// as 0.3.
float groundShare(float roughness) {
    return clamp((kNarrowLobeMaxRoughness - roughness) / 0.1, 0.0, 1.0);
}

// A ground texel (groundTexel; a metal's marker counts as no coverage) over the probes' blend
// (probes.glsl's sampleProbes: rgb premultiplied, a coverage) for a lobe of `roughness`.
vec4 groundOver(vec4 ground, float roughness, vec4 probe) {
    vec4 g = (ground.a > 0.0 ? ground : vec4(0.0)) * groundShare(roughness);
    return g + (1.0 - g.a) * probe;
}

// The ground that ray p + t r meets over the probes' blend, where it lies within groundLimit.
vec4 groundOverProbes(uint count, vec3 p, vec3 r, float roughness, vec4 probe, float proxyDistance) {
    if (count == 0u || groundShare(roughness) <= 0.0) return probe;
    vec3 planeNormal;
    float t;
    return groundOver(groundTexel(count, p, r, roughness, groundLimit(proxyDistance), planeNormal, t), roughness, probe);
}

#endif
