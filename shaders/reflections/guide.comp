#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.guide (reflections.resolution = half): picks the full-resolution pixel that each
// half-resolution trace pixel stands for, and records what the upsampler needs to weigh it.
// Of the 2x2 pixels under a half pixel it prefers reflective ones, then alternates, in a
// checkerboard, the closest and the farthest depth: at a silhouette both surfaces keep samples
// on their side, so that the joint bilateral upsampling finds a match on either side of the edge
// (always the closest would leave the background's pixels next to an edge only foreground
// samples: a halo).
// Out (RGBA32F): xyz the world position of the chosen pixel (so that the upsampler reconstructs
// one position per pixel, not five: a matrix product per sample cost it a third of its time),
// w = packGuide(): the pixel's index in its 2x2 (x + 2 y), its G-buffer roughness and normal,
// positive when it reflects, negative when not (its reflection is 0 and the upsampler gives it
// no weight); reflections/guide_pack.glsl. guidePixel() of common.glsl turns it back into the
// pixel.
#include "reflections/common.glsl"
#include "reflections/material.glsl"
#include "reflections/guide_pack.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;         // texelFetch level 0: .g depth
layout(set = 0, binding = 2) uniform sampler2D normalTex;   // w roughness
layout(set = 0, binding = 3) uniform sampler2D emissiveTex; // a: flags | material index
layout(set = 0, binding = 5, rgba32f) uniform writeonly image2D guideOut;

void main() {
    ivec2 half_ = ivec2(gl_GlobalInvocationID.xy);
    ivec2 fullSize = ivec2(rf.size.xy);
    ivec2 halfSize = (fullSize + 1) / 2;
    if (any(greaterThanEqual(half_, halfSize))) return;
    bool closest = ((half_.x + half_.y) & 1) == 0;
    int bestIndex = 0;
    float bestDepth = -1.0;
    bool bestReflective = false;
    // Straight loop body over the four (lavapipe runs every branch for all lanes anyway).
    for (int i = 0; i < 4; ++i) {
        ivec2 p = min(half_ * 2 + ivec2(i & 1, i >> 1), fullSize - 1);
        float depth = texelFetch(hiz, p, 0).g;
        PixelMaterial m = pixelMaterial(texelFetch(emissiveTex, p, 0).a, texelFetch(normalTex, p, 0).w);
        bool reflective = m.reflective && depth > 0.0;
        bool better = bestDepth < 0.0 || (reflective && !bestReflective) ||
                      (reflective == bestReflective && (closest ? depth > bestDepth : depth < bestDepth));
        if (better) {
            bestIndex = i;
            bestDepth = depth;
            bestReflective = reflective;
        }
    }
    ivec2 best = min(half_ * 2 + ivec2(bestIndex & 1, bestIndex >> 1), fullSize - 1);
    vec3 world = bestDepth > 0.0 ? worldAt(vec2(best) + 0.5, bestDepth) : vec3(0.0);
    vec4 normalRough = texelFetch(normalTex, best, 0);
    imageStore(guideOut, half_, vec4(world, packGuide(bestIndex, bestReflective, normalRough.w, normalRough.xyz)));
}
