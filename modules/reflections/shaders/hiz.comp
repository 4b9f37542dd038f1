#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.hiz: one level of the min/max depth pyramid. Level 0 copies the depth; level N
// reads level N - 1 where a cell covers 2x2 texels, or 3 along an axis for the last cell of an
// odd-sized level, so no texel is lost at any size. x = farthest (smallest reversed-Z value),
// y = closest (largest).
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D src;  // depth (level 0) or level N - 1
layout(set = 0, binding = 2, rg32f) uniform writeonly image2D dst;

layout(push_constant) uniform HiZConstants {
    uint level;
} pc;

void main() {
    ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
    ivec2 dstSize = imageSize(dst);
    if (any(greaterThanEqual(cell, dstSize))) return;
    if (pc.level == 0u) {
        float d = texelFetch(src, cell, 0).r;
        imageStore(dst, cell, vec4(d, d, 0.0, 0.0));
        return;
    }
    ivec2 srcSize = textureSize(src, 0);
    ivec2 lo = cell * 2;
    ivec2 hi = min(lo + 1, srcSize - 1);
    if (cell.x == dstSize.x - 1) hi.x = srcSize.x - 1;
    if (cell.y == dstSize.y - 1) hi.y = srcSize.y - 1;
    float farthest = 1.0 / 0.0;
    float closest = -1.0 / 0.0;
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            vec2 v = texelFetch(src, ivec2(x, y), 0).rg;
            farthest = min(farthest, v.x);
            closest = max(closest, v.y);
        }
    imageStore(dst, cell, vec4(farthest, closest, 0.0, 0.0));
}
