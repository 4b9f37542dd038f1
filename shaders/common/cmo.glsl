// Cubemap tracing through CMOs (seed 000, modules/probes): the records, the face geometry and
// the two tracers. A ray o + t r (o relative to the CMO's centre) is traced against the CMO's
// distance cube: the surface it saw along direction u lies at D(u) from the centre, and the ray
// meets it where delta(t) = |o + t r| - D(u(t)) changes sign from - (in front, seen free) to +.
// No fixed distance threshold: a crossing inside a texel is solved exactly against the texel's
// sphere patch; a crossing at a texel's edge (the ray enters already behind) is a hit only if it
// lies within `tolerance` (the surface's step between texels), else the ray passed behind an
// occluder this CMO cannot see past: unresolved here, the next CMO is asked.
//   cmoTraceHierarchical: per face the ray crosses (at most four, seed 000 theorem 3.3), the
//     min/max distance hierarchy is walked like Hi-Z: a cell whose distance interval the ray's
//     interval over the cell cannot meet is skipped and the level rises, else the walk descends.
//   cmoTraceLinear: constant world steps, bisection refinement; the baseline to beat.
// Before including, define CMO_RECORDS_BINDING, CMO_DISTANCE_BINDING (sampler2DArray RG32F
// min/max, nearest), CMO_LAYERS_BINDING (the radiance array as sampler2DArray, nearest) and
// CMO_ATTR_BINDING, CMO_ALBEDO_BINDING (sampler2DArray, nearest).
#ifndef SPECULUM_CMO_GLSL
#define SPECULUM_CMO_GLSL

#include "common/cmo.h"

layout(set = 0, binding = CMO_RECORDS_BINDING, std430) readonly buffer CmoBuffer {
    CmoRecord cmos[];
};
layout(set = 0, binding = CMO_DISTANCE_BINDING) uniform sampler2DArray cmoDistance;  // min, max
layout(set = 0, binding = CMO_LAYERS_BINDING) uniform sampler2DArray cmoLayers;      // rgb lit, a sun | mirror
layout(set = 0, binding = CMO_ATTR_BINDING) uniform sampler2DArray cmoAttr;          // xyz normal, w roughness
layout(set = 0, binding = CMO_ALBEDO_BINDING) uniform sampler2DArray cmoAlbedo;      // rgb base colour, a metallic

// Vulkan's cube faces (+X, -X, +Y, -Y, +Z, -Z): major axis M, s axis S, t axis T; face
// coordinate s = dot(u, S) / dot(u, M), likewise t, both in [-1, 1]; texel (x, y) of a layer
// covers s in [2x / n - 1, 2(x + 1) / n - 1]. The capture writes faces this way (faceCamera).
const vec3 kCmoM[6] = vec3[](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0), vec3(0, 0, 1), vec3(0, 0, -1));
const vec3 kCmoS[6] = vec3[](vec3(0, 0, -1), vec3(0, 0, 1), vec3(1, 0, 0), vec3(1, 0, 0), vec3(1, 0, 0), vec3(-1, 0, 0));
const vec3 kCmoT[6] = vec3[](vec3(0, -1, 0), vec3(0, -1, 0), vec3(0, 0, 1), vec3(0, 0, -1), vec3(0, -1, 0), vec3(0, -1, 0));

const int kCmoMiss = 0;        // the ray reached its end in front of everything the CMO saw
const int kCmoHit = 1;
const int kCmoUnresolved = 2;  // it passed behind a surface, or starts where the CMO cannot see

int cmoFace(vec3 d) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0 ? 0 : 1;
    if (a.y >= a.z) return d.y >= 0.0 ? 2 : 3;
    return d.z >= 0.0 ? 4 : 5;
}

// The level-0 texel that direction d falls in (face in z).
ivec3 cmoTexel(CmoRecord c, vec3 d) {
    int f = cmoFace(d);
    int n = int(c.center.w);
    vec2 st = vec2(dot(d, kCmoS[f]), dot(d, kCmoT[f])) / dot(d, kCmoM[f]);
    return ivec3(clamp(ivec2(floor((st * 0.5 + 0.5) * float(n))), ivec2(0), ivec2(n - 1)), f);
}

float cmoDistanceAt(CmoRecord c, ivec3 texel) {
    return texelFetch(cmoDistance, ivec3(texel.xy, int(c.params.x) + texel.z), int(c.params.y)).x;
}

// The parameter at which the ray leaves face f's frustum (it is inside at t): the first of the
// four planes dot(q, M +- S) = 0, dot(q, M +- T) = 0 it crosses going out.
float cmoFaceExit(vec3 o, vec3 r, int f) {
    vec3 m = kCmoM[f], s = kCmoS[f], t = kCmoT[f];
    vec4 a = vec4(dot(o, m - s), dot(o, m + s), dot(o, m - t), dot(o, m + t));
    vec4 b = vec4(dot(r, m - s), dot(r, m + s), dot(r, m - t), dot(r, m + t));
    vec4 e = mix(vec4(1e30), -a / min(b, vec4(-1e-20)), lessThan(b, vec4(0.0)));
    return min(min(e.x, e.y), min(e.z, e.w));
}

// How far (world units) a crossing found at a texel's edge may lie behind the surface and
// still be the surface: `thickness` plus the step a surface at 75 degrees to the line of sight
// makes between texels of this level (4 texel footprints).
float cmoTolerance(CmoRecord c, float d, float thickness) {
    return thickness + 4.0 * d * c.params.w;
}

// The parameter where |o + t r| = d going outward (the larger root), clamped to [lo, hi].
float cmoCrossing(vec3 o, vec3 r, float d, float lo, float hi) {
    float b = dot(o, r);
    float disc = b * b - (dot(o, o) - d * d);
    return clamp(-b + sqrt(max(disc, 0.0)), lo, hi);
}

// Hierarchical trace of o + t r, t in [t0, tMax], through CMO c. Returns kCmoHit (tHit set),
// kCmoMiss or kCmoUnresolved; `iterations` counts cells visited (bounded by maxIterations).
int cmoTraceHierarchical(CmoRecord c, vec3 o, vec3 r, float t0, float tMax, float thickness, int maxIterations,
                         inout int iterations, out float tHit) {
    tHit = 0.0;
    int size = int(c.center.w);
    int layer0 = int(c.params.x);
    int base = int(c.params.y);
    int top = int(c.params.z) - 1;
    int level = min(2, top);
    float t = t0;
    {
        // The start must lie in front of what the CMO saw there: behind it, the CMO cannot see
        // the ray's start (or the start offset did not clear the surface's own texel).
        if (length(o + r * t0) > cmoDistanceAt(c, cmoTexel(c, o + r * t0))) return kCmoUnresolved;
    }
    for (int faces = 0; faces < 4 && t < tMax; ++faces) {
        vec3 q = o + r * t;
        int f = cmoFace(q);
        vec3 M = kCmoM[f], S = kCmoS[f], T = kCmoT[f];
        float oM = dot(o, M), oS = dot(o, S), oT = dot(o, T);
        float rM = dot(r, M), rS = dot(r, S), rT = dot(r, T);
        float tFace = min(cmoFaceExit(o, r, f), tMax);
        // The projected ray is a straight line on the face, monotonic in t (seed 000 theorem
        // 3.2): its direction in s and t has a fixed sign over the face.
        float dirS = rS * oM - oS * rM, dirT = rT * oM - oT * rM;
        while (t < tFace && iterations < maxIterations) {
            ++iterations;
            int n = max(size >> level, 1);
            q = o + r * t;
            vec2 st = vec2(dot(q, S), dot(q, T)) / dot(q, M);
            ivec2 cell = clamp(ivec2(floor((st * 0.5 + 0.5) * float(n))), ivec2(0), ivec2(n - 1));
            // The cell's exit: the boundary plane ahead in s and in t (planes through the centre).
            vec2 edge = (vec2(cell + ivec2(dirS > 0.0 ? 1 : 0, dirT > 0.0 ? 1 : 0)) / float(n)) * 2.0 - 1.0;
            float ts = dirS != 0.0 ? -(oS - edge.x * oM) / (rS - edge.x * rM) : 1e30;
            float tt = dirT != 0.0 ? -(oT - edge.y * oM) / (rT - edge.y * rM) : 1e30;
            ts = ts > t ? ts : 1e30;
            tt = tt > t ? tt : 1e30;
            float tb = min(min(ts, tt), tFace);
            vec2 D = texelFetch(cmoDistance, ivec3(cell, layer0 + f), base + level).xy;
            float da = length(q), db = length(o + r * tb);
            float rayMax = max(da, db);
            float nudge = 1e-5 * (1.0 + tb);
            if (rayMax < D.x) {
                // In front of everything this cell saw: skip it, look wider.
                t = tb + nudge;
                level = min(level + 1, top);
                continue;
            }
            if (level > 0) {
                --level;
                continue;
            }
            float d = D.x;
            if (da > d) {
                // Entered behind the texel's surface: the surface itself if the step is small.
                if (da - d <= cmoTolerance(c, d, thickness)) {
                    tHit = t;
                    return kCmoHit;
                }
                return kCmoUnresolved;
            }
            tHit = cmoCrossing(o, r, d, t, tb);
            return kCmoHit;
        }
        t = tFace + 1e-5 * (1.0 + tFace);
        if (iterations >= maxIterations) return kCmoUnresolved;
    }
    return kCmoMiss;
}

// Constant-step trace: delta at every `step`, bisection of the first sign change, the same
// tolerance for what the refined crossing may lie behind.
int cmoTraceLinear(CmoRecord c, vec3 o, vec3 r, float t0, float tMax, float step, float thickness, int maxIterations,
                   inout int iterations, out float tHit) {
    tHit = 0.0;
    if (length(o + r * t0) > cmoDistanceAt(c, cmoTexel(c, o + r * t0))) return kCmoUnresolved;
    float prev = t0;
    for (float t = t0 + step; iterations < maxIterations; t += step) {
        ++iterations;
        t = min(t, tMax);
        vec3 q = o + r * t;
        float d = cmoDistanceAt(c, cmoTexel(c, q));
        if (length(q) > d) {
            float lo = prev, hi = t;
            for (int k = 0; k < 8; ++k) {
                float mid = 0.5 * (lo + hi);
                vec3 m = o + r * mid;
                if (length(m) > cmoDistanceAt(c, cmoTexel(c, m))) hi = mid;
                else lo = mid;
            }
            vec3 h = o + r * hi;
            float dh = cmoDistanceAt(c, cmoTexel(c, h));
            // The refined point lies inside the texel's surface or its step at an edge.
            if (length(h) - dh <= cmoTolerance(c, dh, thickness)) {
                tHit = cmoCrossing(o, r, dh, lo, hi);
                return kCmoHit;
            }
            return kCmoUnresolved;
        }
        if (t >= tMax) return kCmoMiss;
        prev = t;
    }
    return kCmoUnresolved;
}

// Where a ray may start from a surface point p (normal n) that CMO c captured: the surface is
// known only to a texel's footprint there (wider where the CMO sees it at a slant), so the ray
// starts where it has left that footprint behind (seed 000 used one constant bias and found
// it could not be set; this one is per ray).
float cmoStartOffset(CmoRecord c, vec3 p, vec3 n, vec3 r) {
    vec3 toP = p - c.center.xyz;
    float dist = length(toP);
    float slant = max(abs(dot(toP, n)) / max(dist, 1e-6), 0.2);
    float footprint = dist * c.params.w / slant;
    return min(1.5 * footprint / max(dot(r, n), 0.1), 0.5 * dist + 0.05);
}

#endif
