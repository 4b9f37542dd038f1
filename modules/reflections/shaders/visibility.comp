#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.visibility: one level of the pre-integrated visibility pyramid (Uludag 4.4.2).
// In view depth, a coarse cell spans [closest, farthest] of its Hi-Z cell; each covered fine
// cell contributes the share of that span in front of its own closest surface (the empty
// volume a cone passes before meeting it), times its own visibility. Level 0 is fully visible
// and never written: level 1 takes 1 for it instead of reading it.
#include "reflections/shaders/common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;        // all levels
layout(set = 0, binding = 2) uniform sampler2D fineVis;    // level N - 1 (level 1: unread)
layout(set = 0, binding = 3, r8) uniform writeonly image2D dst;

layout(push_constant) uniform VisibilityConstants {
    uint level;
} pc;

void main() {
    ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
    ivec2 dstSize = imageSize(dst);
    if (any(greaterThanEqual(cell, dstSize))) return;
    int level = int(pc.level);
    vec2 coarse = texelFetch(hiz, cell, level).rg;
    float zNear = linearDepth(coarse.y);
    float zFar = linearDepth(coarse.x);
    float span = zFar - zNear;
    ivec2 srcSize = hizLevelSize(level - 1);
    ivec2 lo = cell * 2;
    ivec2 hi = min(lo + 1, srcSize - 1);
    if (cell.x == dstSize.x - 1) hi.x = srcSize.x - 1;
    if (cell.y == dstSize.y - 1) hi.y = srcSize.y - 1;
    float sum = 0.0;
    float count = 0.0;
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            float fineNear = linearDepth(texelFetch(hiz, ivec2(x, y), level - 1).g);
            // A flat cell (no depth span) hides nothing of what is in front of it.
            float empty = span > 1e-6 * zNear ? clamp((fineNear - zNear) / span, 0.0, 1.0) : 1.0;
            sum += empty * (level == 1 ? 1.0 : texelFetch(fineVis, ivec2(x, y), 0).r);
            count += 1.0;
        }
    imageStore(dst, cell, vec4(sum / count));
}
