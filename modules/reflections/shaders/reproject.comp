#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.reproject: level 0 of the colour pyramid. Each pixel takes the previous frame's
// final image (reflections included, so reflections of reflections accumulate over frames,
// Uludag 4.6.4) at the pixel's previous position, when the previous depth there agrees;
// otherwise, and on the first frame, this frame's lit image.
//
// A pixel that does not reflect takes this frame's lit image: what the previous image adds to
// the lit one is a reflection, and this surface has none (the history there is the previous lit
// image, reprojected and filtered: on a still camera within a half-float step of it, with motion
// a staler one). Work follows need (issue 23): with reflections.tiles, level 0 starts as a copy
// of the lit image (reflections.reproject_copy, the same bits this shader gives a pixel that
// does not reflect: the lit image is finite and non-negative, alpha 1) and this shader runs on
// the reflective tiles' footprints only (the resolve's ray and lookup lists).
#include "reflections/shaders/common.glsl"
#include "reflections/shaders/material.glsl"
#include "reflections/shaders/tiles.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D depthTex;
layout(set = 0, binding = 2) uniform sampler2D motionTex;
layout(set = 0, binding = 3) uniform sampler2D litTex;
layout(set = 0, binding = 5) uniform sampler2D historyColor;  // bilinear
layout(set = 0, binding = 7) uniform sampler2D historyDepth;  // texelFetch only
layout(set = 0, binding = 8) uniform sampler2D emissiveTex;   // a: flags | material index (material.glsl)
layout(set = 0, binding = 6, rgba16f) uniform writeonly image2D dst;
// Full-resolution pixels per trace pixel along an axis (2 at half resolution): a tile's footprint.
layout(constant_id = 2) const uint kTileScale = 1u;
// The list this pipeline takes its tiles from (tile mode work; composite.comp says why a
// specialization constant).
layout(constant_id = 3) const uint kList = 0u;

void reprojectPixel(ivec2 pixel) {
    vec3 current = texelFetch(litTex, pixel, 0).rgb;
    vec3 color = current;
    float depth = texelFetch(depthTex, pixel, 0).r;
    bool reflective = depth > 0.0 && pixelMaterial(texelFetch(emissiveTex, pixel, 0).a, 0.0).reflective;
    if (reflective && rf.historyValid != 0u && rf.multiBounce != 0u) {
        vec2 uv = (vec2(pixel) + 0.5) * rf.size.zw;
        // Motion vectors carry object motion too; the expected previous depth is the camera's
        // (static geometry), which is what the depth test below guards.
        vec2 prevUV = uv - texelFetch(motionTex, pixel, 0).rg;
        vec4 prevClip = rfm.prevViewProj * vec4(worldAt(vec2(pixel) + 0.5, depth), 1.0);
        float expectedDepth = prevClip.z / prevClip.w;
        ivec2 prevPixel = ivec2(floor(prevUV * rf.size.xy));
        bool inside = all(greaterThanEqual(prevUV, vec2(0.0))) && all(lessThan(prevUV, vec2(1.0)));
        if (inside) {
            float stored = texelFetch(historyDepth, prevPixel, 0).r;
            bool sameSurface = abs(linearDepth(stored) - linearDepth(expectedDepth)) < 0.02 * linearDepth(expectedDepth);
            vec3 history = textureLod(historyColor, prevUV, 0.0).rgb;
            if (sameSurface && finite3(history)) color = history;
        }
    }
    if (!finite3(color)) color = vec3(0.0);
    imageStore(dst, pixel, vec4(max(color, vec3(0.0)), 1.0));
}

void main() {
    ivec2 size = ivec2(rf.size.xy);
    if (kTileMode == kTileModeScreen) {
        ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
        if (all(lessThan(pixel, size))) reprojectPixel(pixel);
        return;
    }
    ivec2 pixel = footprintBlockPixel(kList, kTileScale);
    if (all(lessThan(pixel, size))) reprojectPixel(pixel);
}
