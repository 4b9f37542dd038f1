#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.lookup_full: at half resolution, the pixels whose chain is lookups only evaluate
// those lookups at their own full-resolution position, over what reflections.upsample wrote.
// Such a pixel's trace pixel (its 2x2's, the guide's) found no screen-space hit and no CMO hit
// (the half-size method image: r and a are 0). Its lookups are the planar probe, the local
// probes and the sky, the resolve's own chain past screen space and the CMOs.
//
// Why: a curved mirror maps the whole room or sky onto a few pixels, so its lookup-only
// reflection changes fast from pixel to pixel, and upsampling it from half size blurs it. With
// the full-resolution values put in place where the full-resolution chain is lookups only, half
// resolution's mirror band would gain 0.15-2.2 dB (plain_metals' sky on its spheres the most;
// MEASUREMENTS.md, issue 23). Every other pixel keeps the upsampled value: nothing is written
// there.
#include "reflections/shaders/common.glsl"
#include "reflections/shaders/material.glsl"
#define PROBES_BUFFER_BINDING 11
#define PROBES_CUBES_BINDING 12
#define PROBES_DISTANCE_BINDING 25
#include "probes/shaders/probes.glsl"
#define PLANAR_BUFFER_BINDING 16
#define PLANAR_IMAGES_BINDING 17
#define GROUND_BUFFER_BINDING 23
#define GROUND_IMAGES_BINDING 24
#include "probes/shaders/planar.glsl"
#include "probes/shaders/ground.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;  // texelFetch
layout(set = 0, binding = 2) uniform sampler2D normalTex;
layout(set = 0, binding = 3) uniform sampler2D emissiveTex;
layout(set = 0, binding = 5) uniform sampler2D methodTex;  // half: the resolve's method weights
layout(set = 0, binding = 8) uniform samplerCube envSpecular;
#include "reflections/shaders/chain.glsl"  // probesAndSky (after envSpecular)
layout(set = 0, binding = 9, rgba16f) uniform writeonly image2D reflectionOut;  // full: the upsampled reflection
// The reflective tiles' footprints (tiles.glsl, as reflections.composite takes them).
#include "reflections/shaders/tiles.glsl"
layout(constant_id = 2) const uint kTileScale = 2u;
layout(constant_id = 3) const uint kList = 0u;

void lookupPixel(ivec2 pixel) {
    vec4 traced = texelFetch(methodTex, pixel >> 1, 0);
    if (traced.r > 0.0 || traced.a > 0.0) return;  // screen space or a CMO served the trace pixel
    float depth;
    vec4 normalRough;
    PixelMaterial m = readSurface(hiz, normalTex, emissiveTex, pixel, depth, normalRough);
    if (!(depth > 0.0 && m.reflective)) return;
    // As reflections.resolve with no screen-space coverage and no CMO hit.
    vec3 p = worldAt(vec2(pixel) + 0.5, depth);
    vec3 n = normalize(normalRough.xyz);
    vec3 r = reflect(normalize(p - rfm.eye), n);
    int planar = rf.planarCount > 0u ? planarAt(rf.planarCount, p, n, rfm.eye) : -1;
    float planarWeight = planar >= 0 ? planarShare(m.roughness) : 0.0;
    vec3 radiance = vec3(0.0);
    if (planarWeight < 1.0) {
        vec4 probe;
        float proxyDistance;
        radiance = probesAndSky(p, n, r, m.roughness, probe, proxyDistance);
    }
    if (planarWeight > 0.0) radiance = mix(radiance, samplePlanar(planar, p, r, m.roughness, distance(p, rfm.eye)).rgb, planarWeight);
    imageStore(reflectionOut, pixel, vec4(max(radiance, vec3(0.0)), 0.0));
}

void main() {
    ivec2 pixel = kTileMode == kTileModeScreen ? ivec2(gl_GlobalInvocationID.xy) : footprintBlockPixel(kList, kTileScale);
    if (all(lessThan(pixel, ivec2(rf.size.xy)))) lookupPixel(pixel);
}
