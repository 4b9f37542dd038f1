#version 460
#extension GL_GOOGLE_include_directive : require
// Test-only (tests/gpu/probes_test.cpp): runs probes/shaders/probes.glsl on a buffer of queries so the
// CPU can check the parallax lookup and the blend against analytic ray-shape intersections.
// Per query i, results[4i .. 4i+3]: probeDirection for probe 0, for probe 1 (when there is one),
// the influences (x probe 0, y probe 1), and sampleProbes(probe count, ...) (rgb, a total weight).
#define PROBES_BUFFER_BINDING 0
#define PROBES_CUBES_BINDING 1
#include "probes/shaders/probes.glsl"

layout(local_size_x = 64) in;

struct Query {
    vec4 p;  // xyz world point, w roughness
    vec4 n;  // xyz unit normal
    vec4 r;  // xyz unit reflection direction
};
layout(set = 0, binding = 2, std430) readonly buffer Queries {
    Query queries[];
};
layout(set = 0, binding = 3, std430) writeonly buffer Results {
    vec4 results[];
};

layout(push_constant) uniform Push {
    uvec4 info;  // x query count, y probe count (1 or 2)
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.info.x) return;
    Query q = queries[i];
    vec3 p = q.p.xyz, n = q.n.xyz, r = q.r.xyz;
    bool two = pc.info.y > 1u;
    results[4u * i + 0u] = vec4(probeDirection(probes[0], p, r), 0.0);
    results[4u * i + 1u] = two ? vec4(probeDirection(probes[1], p, r), 0.0) : vec4(0.0);
    results[4u * i + 2u] = vec4(probeInfluence(probes[0], p, n), two ? probeInfluence(probes[1], p, n) : 0.0, 0.0, 0.0);
    results[4u * i + 3u] = sampleProbes(pc.info.y, p, n, r, q.p.w);
}
