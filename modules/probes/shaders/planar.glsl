// Planar probes in a shader (modules/probes/planar.cpp renders them): the fallback chain's
// planar step, after screen space and before the CMOs. A pixel is served by the first planar
// probe whose plane it lies on (distance and normal within the record's tolerances, inside its
// extents, the eye in front): the mirrored view was rendered with the view's own projection, so
// the plane's point p is read at p's own UV; a normal that is not the plane's (a bump, a
// tolerance) reads where p + r * d lands, d the mirrored distance there; a glossy lobe reads
// the mip of its cone's footprint at that distance. Before including, define
// PLANAR_BUFFER_BINDING and PLANAR_IMAGES_BINDING (set 0).
#ifndef SPECULUM_PLANAR_GLSL
#define SPECULUM_PLANAR_GLSL

#include "common/brdf.glsl"  // coneTan
#include "probes/shaders/probe.h"

layout(set = 0, binding = PLANAR_BUFFER_BINDING, std430) readonly buffer PlanarBuffer {
    PlanarProbe planars[];
};
layout(set = 0, binding = PLANAR_IMAGES_BINDING) uniform sampler2DArray planarImages;  // trilinear clamp

// The index of the planar probe serving world point p with normal n seen from `eye`, or -1.
int planarAt(uint count, vec3 p, vec3 n, vec3 eye) {
    for (uint i = 0u; i < count; ++i) {
        PlanarProbe pl = planars[i];
        float s = dot(pl.plane.xyz, p) + pl.plane.w;
        vec3 lp = (pl.worldToPlane * vec4(p, 1.0)).xyz;
        // The depth buffer's reconstruction error grows with distance: 0.2% of it.
        bool onPlane = abs(s) <= pl.extents.w + 0.002 * distance(p, eye) && dot(n, pl.plane.xyz) >= pl.extents.z &&
                       abs(lp.x) <= pl.extents.x && abs(lp.z) <= pl.extents.y &&
                       dot(pl.plane.xyz, eye) + pl.plane.w > 0.0;
        if (onPlane) return int(i);
    }
    return -1;
}

// How much of a pixel of `roughness` on its plane the planar probe takes: all up to 0.2, none
// from 0.3 (the rough band), linear between. The image's box mips stand in for a GGX lobe only
// while the lobe is narrow: serving the gallery's 0.3 and 0.6 floor bands too cost its rough
// band 3.5 dB (modules/reflections/MEASUREMENTS.md, "planar probes"); above, the chain answers.
float planarShare(float roughness) {
    return clamp((kNarrowLobeMaxRoughness - roughness) / 0.1, 0.0, 1.0);
}

vec2 planarUv(PlanarProbe pl, vec3 q) {
    vec4 c = pl.viewProj * vec4(q, 1.0);
    return c.xy / c.w * 0.5 + 0.5;
}

// The reflected distance (m; 65504 the sky) of the mirror ray at plane point p: the planar
// image's texel at p, nearest (a bilinear mix across a silhouette would average a near surface
// with the sky).
float planarDistance(int index, vec3 p) {
    PlanarProbe pl = planars[index];
    int base = int(pl.params.y);
    ivec2 size = textureSize(planarImages, base).xy;
    ivec2 texel = clamp(ivec2(clamp(planarUv(pl, p), pl.crop.xy, pl.crop.zw) * vec2(size)), ivec2(0), size - 1);
    return texelFetch(planarImages, ivec3(texel, int(pl.params.x)), base).a;
}

// rgb: the reflection of ray p + t r at `roughness` from planar probe `index`; a: the reflected
// distance (m; 65504 the sky).
vec4 samplePlanar(int index, vec3 p, vec3 r, float roughness, float eyeDistance) {
    PlanarProbe pl = planars[index];
    float layer = pl.params.x, base = pl.params.y;
    float d = planarDistance(index, p);
    vec2 uv = planarUv(pl, p + r * min(d, 1e4));
    // The cone's footprint at the reflected surface over a planar pixel there (seen from the
    // mirrored eye, eyeDistance + d away).
    float footprint = 2.0 * coneTan(roughness) * min(d, 1e4) / max(pl.params.z * (eyeDistance + min(d, 1e4)), 1e-9);
    float lod = clamp(base + log2(max(footprint, 1.0)), base, pl.params.w);
    // Within the texels rendered this time (planar.cpp, planarFootprint): a bumped or glossy
    // ray reaching past them reads the crop's edge, never the layer's stale texels.
    vec3 c = textureLod(planarImages, vec3(clamp(uv, pl.crop.xy, pl.crop.zw), layer), lod).rgb;
    return vec4(c, d);
}

#endif
