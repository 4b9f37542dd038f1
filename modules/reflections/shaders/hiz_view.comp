#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.hiz_view: the `hiz` AOV, one Hi-Z level at full resolution: r closest and
// g farthest view distance of the pixel's cell (m), b the level.
#include "reflections/shaders/common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;
layout(set = 0, binding = 2, rgba16f) uniform writeonly image2D dst;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, ivec2(rf.size.xy)))) return;
    int level = min(int(rf.debugHizMip), int(rf.hizLevels) - 1);
    ivec2 cell = min(pixel >> level, hizLevelSize(level) - 1);
    vec2 mm = texelFetch(hiz, cell, level).rg;
    // 65504 is the largest half float: the sky's infinite distance saturates there.
    imageStore(dst, pixel, vec4(min(linearDepth(mm.y), 65504.0), min(linearDepth(mm.x), 65504.0), float(level), 1.0));
}
