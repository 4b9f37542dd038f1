// Local cubemap probes in a shader (modules/probes): the shader-visible record, declared once
// (probes/shaders/probe.h, shared with C++), and
// the fallback chain's probe step: per pixel, probes in priority order (the buffer is sorted by
// order, then by smallest volume) are blended by their influence weights until the weight
// reaches 1; the caller gives the rest to the sky. Before including, define
// PROBES_BUFFER_BINDING and PROBES_CUBES_BINDING (set 0).
#ifndef SPECULUM_PROBES_GLSL
#define SPECULUM_PROBES_GLSL

#include "probes/shaders/probe.h"

layout(set = 0, binding = PROBES_BUFFER_BINDING, std430) readonly buffer ProbeBuffer {
    Probe probes[];
};
layout(set = 0, binding = PROBES_CUBES_BINDING) uniform samplerCubeArray probeCubes;

// Influence of a probe at world point p with unit normal n: 1 inside the shape, falling linearly
// to 0 at the blend distance outside it (distances in node space). The blend zone lies outside
// because one shape is both proxy and influence: a room's walls lie on the proxy and must get
// the full weight. In that outer zone a normal-facing fade removes surfaces that face away from
// the capture point: the far side of a wall, which the probe never saw. Inside the shape every
// surface keeps its weight (the back of a sphere faces away from the capture point too, and
// what it reflects is the room).
float probeInfluence(Probe pr, vec3 p, vec3 n) {
    vec3 lp = (pr.worldToLocal * vec4(p, 1.0)).xyz;
    vec3 d = pr.extents.xyz - abs(lp);
    float inside = pr.center.w < 0.5 ? min(d.x, min(d.y, d.z)) : pr.extents.x - length(lp);
    float w = pr.extents.w > 0.0 ? clamp(1.0 + inside / pr.extents.w, 0.0, 1.0) : (inside >= 0.0 ? 1.0 : 0.0);
    vec3 toCenter = pr.center.xyz - p;
    float len = length(toCenter);
    float facing = len > 1e-4 ? dot(n, toCenter) / len : 1.0;
    // Outside: full weight down to facing -0.2 (grazing walls keep it), none below -0.5.
    return w * (inside >= 0.0 ? 1.0 : clamp((facing + 0.5) / 0.3, 0.0, 1.0));
}

// Parallax correction (Lagarde & Zanuttini 2012): the ray p + t r meets the proxy (box or
// sphere in node space) at t; the cube is looked up toward that point from the capture point.
// An affine map keeps the ray's parameter, so t found in node space holds in world space.
float probeProxyT(Probe pr, vec3 p, vec3 r) {
    vec3 lp = (pr.worldToLocal * vec4(p, 1.0)).xyz;
    vec3 lr = (pr.worldToLocal * vec4(r, 0.0)).xyz;
    lr = mix(lr, sign(lr) * 1e-8, lessThan(abs(lr), vec3(1e-8)));
    vec3 inv = 1.0 / lr;
    vec3 tf = max((pr.extents.xyz - lp) * inv, (-pr.extents.xyz - lp) * inv);
    float tBox = min(tf.x, min(tf.y, tf.z));
    float a = dot(lr, lr), b = dot(lp, lr), c = dot(lp, lp) - pr.extents.x * pr.extents.x;
    float tSphere = (-b + sqrt(max(b * b - a * c, 0.0))) / a;
    return max(pr.center.w < 0.5 ? tBox : tSphere, 0.0);
}

vec3 probeDirection(Probe pr, vec3 p, vec3 r) {
    return p + r * probeProxyT(pr, p, r) - pr.center.xyz;
}

// rgb: the probes' blended radiance (already weighted), a: the weight of what they captured
// (at most 1). A cube's alpha is its coverage by geometry (0 where the probe saw the sky, which
// is infinitely far and goes to the caller's sky along r instead), its rgb premultiplied by it;
// the caller gives 1 - a to the sky.
// `proxyDistance`: the influence-weighted distance along r to the probes' proxies (0 where no
// probe reaches p), which the temporal pass reprojects the reflection by.
vec4 sampleProbes(uint count, vec3 p, vec3 n, vec3 r, float roughness, out float proxyDistance) {
    vec3 sum = vec3(0.0);
    float covered = 0.0;
    float total = 0.0;
    float distanceSum = 0.0;
    for (uint i = 0u; i < count; ++i) {
        Probe pr = probes[i];
        float w = max(min(probeInfluence(pr, p, n), 1.0 - total), 0.0);
        float t = probeProxyT(pr, p, r);
        vec4 c = textureLod(probeCubes, vec4(p + r * t - pr.center.xyz, pr.params.x), roughness * pr.params.y);
        sum += c.rgb * w;
        covered += c.a * w;
        total += w;
        distanceSum += t * w;
        if (total >= 0.999) break;
    }
    proxyDistance = total > 0.0 ? distanceSum / total : 0.0;
    return vec4(sum, covered);
}

vec4 sampleProbes(uint count, vec3 p, vec3 n, vec3 r, float roughness) {
    float unused;
    return sampleProbes(count, p, n, r, roughness, unused);
}

#endif
