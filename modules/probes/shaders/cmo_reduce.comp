#version 460
// probes.cmo_hierarchy: one level of a CMO's min/max distance hierarchy from the level below
// (x the nearest, y the farthest surface in the cell). CMO faces are powers of two, so every
// cell is exactly its four children: the hierarchy is exact at every level.
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2DArray finer;  // texelFetch, mip 0 of its view
layout(set = 0, binding = 1, rg32f) uniform writeonly image2DArray coarser;

layout(push_constant) uniform Push {
    uvec4 info;  // x coarser size, y first layer
} pc;

void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID.xy, int(gl_GlobalInvocationID.z + pc.info.y));
    if (any(greaterThanEqual(cell.xy, ivec2(pc.info.x)))) return;
    ivec2 c = cell.xy * 2;
    vec2 a = texelFetch(finer, ivec3(c, cell.z), 0).xy;
    vec2 b = texelFetch(finer, ivec3(c + ivec2(1, 0), cell.z), 0).xy;
    vec2 e = texelFetch(finer, ivec3(c + ivec2(0, 1), cell.z), 0).xy;
    vec2 f = texelFetch(finer, ivec3(c + ivec2(1, 1), cell.z), 0).xy;
    imageStore(coarser, cell, vec4(min(min(a.x, b.x), min(e.x, f.x)), max(max(a.y, b.y), max(e.y, f.y)), 0.0, 0.0));
}
