#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.refresh (reflections.ray_budget=quarter): a ray per 2x2 block per frame, amortized
// over four. The trace, CMO trace and resolve ran on the half-size grid, each half pixel at the
// full pixel of its block that reflections.classify chose this frame (the choice rotates, so every
// reflective pixel is chosen at least once in four frames; guide.glsl). Here, per full pixel:
//   - the pixel chosen this frame takes its resolved value as it is (the same ray and cone as at
//     full rate: trace and resolve work in full-resolution pixel coordinates);
//   - any other keeps its own last value, reprojected by its surface (and by the reflected point
//     on sharp surfaces, as reflections.temporal does) where the previous frame saw the same
//     surface with the same normal and roughness. On a still camera nothing is clipped: each
//     pixel then holds its own traced value within four frames and the image is the full-rate
//     one (tests/stability/ray_budget_test.py). While the camera moves the history is clipped to
//     the upsampled neighbourhood, so that a stale value is never further off than upsampling;
//   - where there is no such history (disocclusion, the first frames), the joint bilateral
//     upsampling of the half-size image, as reflections.resolution=half gives (upsample.glsl:
//     computed here, only for the pixels that use it, so no upsampling pass runs for the
//     reflection: a still view pays for none of it).
// No pixel's value is older than three frames: objects moving under a still camera lag that much.
// Frostbite's stochastic SSR (Stachowiak 2015) and Lumen amortize rays the same way.
#include "reflections/shaders/common.glsl"
#include "reflections/shaders/material.glsl"
#include "reflections/shaders/guide.glsl"
#include "reflections/shaders/upsample.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;            // level 0 .g: depth
layout(set = 0, binding = 2) uniform sampler2D normalTex;      // xyz normal, w roughness
layout(set = 0, binding = 3) uniform sampler2D emissiveTex;    // a: flags | material index
layout(set = 0, binding = 5) uniform sampler2D motionTex;      // uv - previous uv
layout(set = 0, binding = 7) uniform sampler2D halfTex;        // half: the resolve's reflection
layout(set = 0, binding = 8) uniform sampler2D guideTex;       // half: guidePixel()
layout(set = 0, binding = 9) uniform sampler2D distanceTex;    // half: reflected distance (resolve)
layout(set = 0, binding = 10) uniform sampler2D historyTex;    // texelFetch: last frame's refreshed
layout(set = 0, binding = 11) uniform sampler2D historyNormal; // texelFetch: xyz normal, w roughness (< 0 none)
layout(set = 0, binding = 12) uniform sampler2D historyDepth;  // texelFetch
layout(set = 0, binding = 13, rgba16f) uniform writeonly image2D refreshedOut;
layout(set = 0, binding = 14, rgba16f) uniform writeonly image2D normalOut;

#include "reflections/shaders/reprojection.glsl"

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(rf.size.xy);
    if (any(greaterThanEqual(pixel, size))) return;
    float depth;
    vec4 normalRough;
    PixelMaterial m = readSurface(hiz, normalTex, emissiveTex, pixel, depth, normalRough);
    if (!(depth > 0.0 && m.reflective)) {
        imageStore(refreshedOut, pixel, vec4(0.0));
        imageStore(normalOut, pixel, vec4(0.0, 0.0, 0.0, -1.0));
        return;
    }
    vec3 n = normalize(normalRough.xyz);
    ivec2 halfPixel = min(pixel >> 1, ((size + 1) >> 1) - 1);
    bool fresh = all(equal(guidePixel(halfPixel, texelFetch(guideTex, halfPixel, 0)), pixel));
    if (fresh) {
        imageStore(refreshedOut, pixel, texelFetch(halfTex, halfPixel, 0));
        imageStore(normalOut, pixel, vec4(n, m.roughness));
        return;
    }
    vec3 p = worldAt(vec2(pixel) + 0.5, depth);
    ivec2 halfSize = (size + 1) >> 1;
    float invDist = 1.0 / max(distance(p, rfm.eye), 1e-6);
    bool validS = false, moving = false;
    vec4 h = vec4(0.0);
    ivec2 prevSPixel = ivec2(0);
    if (rf.refreshValid != 0u) {
        vec2 uv = (vec2(pixel) + 0.5) * rf.size.zw;
        vec2 prevS;
        validS = surfaceHistory(pixel, p, n, m.roughness, prevS, prevSPixel);
        if (validS) h = texelFetch(historyTex, prevSPixel, 0);
        // Moving: the camera (beyond rounding) or this pixel's surface (its motion vector).
        moving = rf.cameraMoved != 0u || any(greaterThan(abs(prevS - uv) * rf.size.xy, vec2(0.01)));
    }
    // Still with a history: the history as it is (alpha, the coverage debug view's, with it).
    // Otherwise the upsampled value, which a moving pixel's history is then clipped to. One call
    // site, which also returns the four half-size samples' box: the clip used to fetch them again
    // and the fallback inlined a second upsampling (lavapipe pays for both sides of a branch its
    // lanes split on; MEASUREMENTS.md, issue 23, 2026-12-06).
    bool still = validS && !moving && finite3(h.rgb);
    vec4 result = vec4(max(h.rgb, vec3(0.0)), h.a);
    vec3 lo, hi;
    if (!still) result = bilateralUpsampleBox(guideTex, halfTex, halfSize, pixel, p, n, normalRough.w, invDist, lo, hi);
    if (validS && moving) {
        // The reflected point's previous position for sharp surfaces (temporal.comp's rule).
        float sharp = 1.0 - smoothstep(0.05, 0.35, m.roughness);
        ivec2 prevVPixel;
        if (sharp > 0.0 && reflectedHistory(p, texelFetch(distanceTex, halfPixel, 0).r, n, m.roughness, prevVPixel))
            h.rgb = mix(h.rgb, texelFetch(historyTex, prevVPixel, 0).rgb, sharp);
        // Clipped to the box of this pixel's upsampled value and the four half-size samples
        // around it.
        vec3 clipped = clamp(h.rgb, min(lo, result.rgb), max(hi, result.rgb));
        if (finite3(clipped)) result.rgb = max(clipped, vec3(0.0));
    }
    imageStore(refreshedOut, pixel, result);
    imageStore(normalOut, pixel, vec4(n, m.roughness));
}
