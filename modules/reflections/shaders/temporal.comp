#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.temporal: accumulates the reflection over frames, before the composite.
// Where the history comes from depends on what the reflection is of:
//   rough reflections follow the surface: the history at the pixel's motion vector;
//   sharp ones follow the reflected point: its mirror image behind the surface (the view ray
//   extended by the reflected distance (the resolve's distance image); the sky's is a direction) projected by the
//   previous camera, the parallax a planar mirror shows (Stachowiak's SSSR, HDRP).
// The two are blended by roughness (the reflected point's weight falls from 1 at 0.05 to 0 at
// 0.35, where a lobe's footprint is wider than its parallax). Each is rejected where the
// previous frame saw another surface there: depth off by more than 2% (the surface's), normal
// off by more than 25 degrees (18 for the reflected point's), roughness changed by more than
// 0.1; a surface that was hidden (disoccluded) takes no history at all.
// The history left is clipped to the current 3x3 neighbourhood's mean +- temporal_clip
// standard deviations (Salvi's variance clipping) and blended with weight temporal_alpha for
// this frame. Without a history (first frame, cut, resize, settings change) this frame is the
// output, so a still camera starts exact and stays there: no bias, no drift.
#include "reflections/shaders/common.glsl"
#include "reflections/shaders/material.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;             // level 0 .g: depth
layout(set = 0, binding = 2) uniform sampler2D normalTex;       // xyz normal, w roughness
layout(set = 0, binding = 3) uniform sampler2D emissiveTex;     // a: flags | material index
layout(set = 0, binding = 5) uniform sampler2D motionTex;       // uv - previous uv
layout(set = 0, binding = 6) uniform sampler2D reflectionTex;   // this frame's, full size
layout(set = 0, binding = 7) uniform sampler2D distanceTex;       // trace size; r: reflected distance (resolve)
layout(set = 0, binding = 8) uniform sampler2D historyTex;      // texelFetch: accumulated reflection
layout(set = 0, binding = 9) uniform sampler2D historyNormal;   // texelFetch: xyz normal, w roughness (< 0 none)
layout(set = 0, binding = 10) uniform sampler2D historyDepth;   // texelFetch
layout(set = 0, binding = 11, rgba16f) uniform writeonly image2D accumulatedOut;
layout(set = 0, binding = 12, rgba16f) uniform writeonly image2D normalOut;


#include "reflections/shaders/reprojection.glsl"

// Clips h to the box [lo, hi] along the line to the box's centre (Playdead's TAA).
vec3 clipToBox(vec3 h, vec3 lo, vec3 hi) {
    vec3 c = 0.5 * (lo + hi), e = 0.5 * (hi - lo) + 1e-4;
    vec3 a = abs((h - c) / e);
    float m = max(a.x, max(a.y, a.z));
    return m > 1.0 ? c + (h - c) / m : h;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(rf.size.xy);
    if (any(greaterThanEqual(pixel, size))) return;
    float depth;
    vec4 normalRough;
    PixelMaterial m = readSurface(hiz, normalTex, emissiveTex, pixel, depth, normalRough);
    if (!(depth > 0.0 && m.reflective)) {
        imageStore(accumulatedOut, pixel, vec4(0.0));
        imageStore(normalOut, pixel, vec4(0.0, 0.0, 0.0, -1.0));
        return;
    }
    vec3 n = normalize(normalRough.xyz);
    vec4 current = texelFetch(reflectionTex, pixel, 0);
    vec4 result = current;
    if (rf.temporalValid != 0u) {
        // The neighbourhood's mean and standard deviation (3x3, clamped at the screen's edges).
        vec3 m1 = vec3(0.0), m2 = vec3(0.0);
        for (int i = 0; i < 9; ++i) {
            vec3 c = texelFetch(reflectionTex, clamp(pixel + ivec2(i % 3 - 1, i / 3 - 1), ivec2(0), size - 1), 0).rgb;
            m1 += c;
            m2 += c * c;
        }
        m1 /= 9.0;
        vec3 sigma = sqrt(max(m2 / 9.0 - m1 * m1, vec3(0.0)));
        vec3 p = worldAt(vec2(pixel) + 0.5, depth);
        // The surface's previous position, checked against the previous depth as reproject.comp does.
        vec2 prevS;
        ivec2 prevSPixel;
        bool validS = surfaceHistory(pixel, p, n, m.roughness, prevS, prevSPixel);
        // The reflected point's previous position.
        float dist = texelFetch(distanceTex, ivec2(vec2(pixel) / rf.traceScale), 0).r;  // at the trace's size
        ivec2 prevVPixel;
        bool validV = reflectedHistory(p, dist, n, m.roughness, prevVPixel);
        float sharp = 1.0 - smoothstep(0.05, 0.35, m.roughness);
        // A surface the previous frame did not see (disocclusion) has no history at all: the
        // reflected point's may look valid there (the mirror beside it) but belongs to pixels
        // the occluder's reflection was in (tests/stability: 12% left after 8 frames with it).
        float wV = validS && validV ? sharp : 0.0;
        float wS = validS ? 1.0 - wV : 0.0;
        if (wS + wV > 0.0) {
            vec3 h = vec3(0.0);
            // The texels whose surface was checked, not a bilinear blend: a blend takes the other
            // side of a disocclusion's edge too (tests/stability: 27% off at the motion's end).
            if (wS > 0.0) h += wS * texelFetch(historyTex, prevSPixel, 0).rgb;
            if (wV > 0.0) h += wV * texelFetch(historyTex, prevVPixel, 0).rgb;
            // The box always holds this frame's own value: a one-pixel feature (a thin post's
            // reflection) lies outside its neighbourhood's spread, and clipping the history
            // there would bias a still image toward the neighbours for ever (tests/stability).
            vec3 lo = min(m1 - rf.temporalClip * sigma, current.rgb), hi = max(m1 + rf.temporalClip * sigma, current.rgb);
            h = clipToBox(h / (wS + wV), lo, hi);
            vec3 blended = mix(h, current.rgb, rf.temporalAlpha);
            if (finite3(blended)) result.rgb = max(blended, vec3(0.0));
        }
    }
    imageStore(accumulatedOut, pixel, result);
    imageStore(normalOut, pixel, vec4(n, m.roughness));
}
