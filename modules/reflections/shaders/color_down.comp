#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.color_pyramid: level N of the pre-convolved colour pyramid from level N - 1
// (Uludag 4.5.4): the normalized 7-tap Gaussian (0.001 0.028 0.233 0.474 0.233 0.028 0.001)
// centred on the coarse texel, whose centre falls between two fine texels, so each tap is the
// mean of two: 8 fine weights per axis. Alpha is the visibility pyramid's level N (binding 3).
//
// The 8 x 8 fine footprint is read as 4 x 4 bilinear lookups: each lookup lands between a pair
// of fine texels at the ratio of their weights, so it returns their weighted mean, and the pair's
// weight multiplies it (the sampler clamps to the edge as the fetches' clamp did). 16 lookups a
// texel and no shared memory: on lavapipe the shared-memory version (22 x 22 texels a group,
// two barriers) cost 60 ms for level 1 of a 960x540 frame; this costs about a quarter of it
// (modules/reflections/MEASUREMENTS.md). The filter is the same; the lookups' weights are the
// sampler's (8 sub-texel bits on most GPUs), within 1/256 of the pairs' ratios.
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D src;  // level N - 1, bilinear, clamp to edge
layout(set = 0, binding = 2, rgba16f) uniform writeonly image2D dst;
// Level N of the visibility pyramid, carried in alpha so that the resolve's cone samples get
// colour and visibility from one trilinear lookup (same sizes per level).
layout(set = 0, binding = 3) uniform sampler2D visibilityLevel;

// The fine weights in pairs (0.0005 0.0145 | 0.1305 0.3535 | 0.3535 0.1305 | 0.0145 0.0005):
// each pair's sum, and where between its two texels the lookup lands (the second's share).
const float kPairWeight[4] = float[4](0.015, 0.484, 0.484, 0.015);
const float kPairOffset[4] = float[4](0.0145 / 0.015, 0.3535 / 0.484, 0.1305 / 0.484, 0.0005 / 0.015);

void main() {
    ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
    ivec2 dstSize = imageSize(dst);
    if (any(greaterThanEqual(cell, dstSize))) return;
    vec2 invSrc = 1.0 / vec2(textureSize(src, 0));
    // Fine texel of tap 0: 2 * cell - 3; pair p starts at tap 2p. Texel j's centre is j + 0.5.
    vec2 first = vec2(cell * 2 - 3) + 0.5;
    vec3 sum = vec3(0.0);
    for (int py = 0; py < 4; ++py) {
        float y = (first.y + float(2 * py) + kPairOffset[py]) * invSrc.y;
        vec3 row = vec3(0.0);
        for (int px = 0; px < 4; ++px) {
            float x = (first.x + float(2 * px) + kPairOffset[px]) * invSrc.x;
            row += kPairWeight[px] * textureLod(src, vec2(x, y), 0.0).rgb;
        }
        sum += kPairWeight[py] * row;
    }
    imageStore(dst, cell, vec4(sum, texelFetch(visibilityLevel, cell, 0).r));
}
