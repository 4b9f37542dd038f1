#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.hiz.0: the Hi-Z pyramid's levels 0 and 1 and the visibility pyramid's level 1 in
// one pass, one invocation per level-1 cell. The cell's depth texels (2x2, or 3 along an axis
// for the last cell of an odd size: hiz.comp's rule) are copied to level 0, their min and max
// are level 1, and level-1 visibility is computed from the same values in registers, as
// visibility.comp does from the written levels (level 0 is fully visible). Three passes were
// one full-resolution and two quarter-resolution dispatches, the later two re-reading what the
// first wrote: 4.9 + 3.6 + 4.0 ms at 960x540 on lavapipe (MEASUREMENTS, issue 23).
#include "reflections/shaders/common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D depthTex;
layout(set = 0, binding = 2, rg32f) uniform writeonly image2D level0;
layout(set = 0, binding = 3, rg32f) uniform writeonly image2D level1;
layout(set = 0, binding = 5, r8) uniform writeonly image2D visibility1;

void main() {
    ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
    ivec2 cells = imageSize(level1);
    if (any(greaterThanEqual(cell, cells))) return;
    ivec2 srcSize = textureSize(depthTex, 0);
    ivec2 lo = cell * 2;
    ivec2 hi = min(lo + 1, srcSize - 1);
    if (cell.x == cells.x - 1) hi.x = srcSize.x - 1;
    if (cell.y == cells.y - 1) hi.y = srcSize.y - 1;
    // A 3x3 loop of constant trip count with its indices known after unrolling: the depths stay
    // in registers (a dynamically indexed array goes to memory on a CPU driver), and the third
    // row and column, which only the last cells have, cost nothing where all lanes skip them.
    float farthest = 1.0 / 0.0;
    float closest = -1.0 / 0.0;
    float depths[9];
    for (int j = 0; j < 9; ++j) {
        ivec2 texel = lo + ivec2(j % 3, j / 3);
        depths[j] = 0.0;
        if (all(lessThanEqual(texel, hi))) {
            float d = texelFetch(depthTex, texel, 0).r;
            imageStore(level0, texel, vec4(d, d, 0.0, 0.0));
            farthest = min(farthest, d);
            closest = max(closest, d);
            depths[j] = d;
        }
    }
    imageStore(level1, cell, vec4(farthest, closest, 0.0, 0.0));
    // visibility.comp at level 1 (a fine cell's closest is its depth; its visibility is 1), summed
    // in its order (rows, then columns).
    float zNear = linearDepth(closest);
    float span = linearDepth(farthest) - zNear;
    float sum = 0.0;
    float count = 0.0;
    for (int j = 0; j < 9; ++j) {
        if (all(lessThanEqual(lo + ivec2(j % 3, j / 3), hi))) {
            sum += span > 1e-6 * zNear ? clamp((linearDepth(depths[j]) - zNear) / span, 0.0, 1.0) : 1.0;
            count += 1.0;
        }
    }
    imageStore(visibility1, cell, vec4(sum / count));
}
