#version 460
#extension GL_GOOGLE_include_directive : require
// Test-only (tests/gpu/cmo_test.cpp): runs both tracers of common/cmo.glsl on a buffer of rays
// through CMO 0, so the CPU can check hits against analytic ray casts and the two tracers
// against each other. Per query i: results[2i] hierarchical, results[2i + 1] linear, each
// (status, tHit, iterations, 0).
#define CMO_RECORDS_BINDING 0
#define CMO_DISTANCE_BINDING 1
#define CMO_LAYERS_BINDING 2
#define CMO_ATTR_BINDING 3
#define CMO_ALBEDO_BINDING 4
#include "probes/shaders/cmo.glsl"

layout(local_size_x = 64) in;

struct Query {
    vec4 origin;  // xyz world, w 1: on a surface (it leaves it by `normal`, cmoLeaveSurface), 0: in the open
    vec4 dir;     // xyz unit, w the ray's length
    vec4 normal;  // xyz the surface's normal when w of origin is 1
};
layout(set = 0, binding = 5, std430) readonly buffer Queries {
    Query queries[];
};
layout(set = 0, binding = 6, std430) writeonly buffer Results {
    vec4 results[];
};

layout(push_constant) uniform Push {
    vec4 params;  // x linear step, y thickness, z max iterations, w query count
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(pc.params.w)) return;
    Query q = queries[i];
    CmoRecord c = cmos[0];
    vec3 o = q.origin.xyz - c.center.xyz;
    vec3 n = q.origin.w > 0.5 ? q.normal.xyz : vec3(0.0);
    int maxIterations = int(pc.params.z);
    int itH = 0, itL = 0;
    float tH, tL;
    int sH = cmoTraceHierarchical(c, o, q.dir.xyz, n, q.dir.w, pc.params.y, maxIterations, false, itH, tH);
    int sL = cmoTraceLinear(c, o, q.dir.xyz, n, q.dir.w, pc.params.x, pc.params.y, maxIterations, false, itL, tL);
    results[2u * i] = vec4(float(sH), tH, float(itH), 0.0);
    results[2u * i + 1u] = vec4(float(sL), tL, float(itL), 0.0);
}
