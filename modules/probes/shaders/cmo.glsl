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

#include "probes/shaders/cmo.h"

layout(set = 0, binding = CMO_RECORDS_BINDING, std430) readonly buffer CmoBuffer {
    CmoRecord cmos[];
};
layout(set = 0, binding = CMO_DISTANCE_BINDING) uniform sampler2DArray cmoDistance;  // min, max
layout(set = 0, binding = CMO_LAYERS_BINDING) uniform sampler2DArray cmoLayers;      // rgb lit, a cmoUnpackFlags
layout(set = 0, binding = CMO_ATTR_BINDING) uniform sampler2DArray cmoAttr;          // xyz normal, w roughness
layout(set = 0, binding = CMO_ALBEDO_BINDING) uniform sampler2DArray cmoAlbedo;      // rgb base colour, a metallic

// A texel's alpha in cmoLayers (probes.cmo_store): the sun's visibility (0-1) + 2 if its material
// is mirror-masked (SPECULUM_reflections mirrorForSelfReflections) + 4 if it is reflective.
void cmoUnpackFlags(float a, out float sun, out bool mirror, out bool reflective) {
    reflective = a >= 3.5;
    a -= reflective ? 4.0 : 0.0;
    mirror = a >= 1.5;
    sun = a - (mirror ? 2.0 : 0.0);
}

// Vulkan's cube faces (+X, -X, +Y, -Y, +Z, -Z): major axis M, s axis S, t axis T; face
// coordinate s = dot(u, S) / dot(u, M), likewise t, both in [-1, 1]; texel (x, y) of a layer
// covers s in [2x / n - 1, 2(x + 1) / n - 1]. The capture writes faces this way (faceCamera).
// Selects, not tables: a table indexed by a per-lane face goes to memory on a SIMD CPU driver
// (STYLE.md), and the walk reads the axes at every face it crosses.
void cmoAxes(int f, out vec3 m, out vec3 s, out vec3 t) {
    float sg = (f & 1) != 0 ? -1.0 : 1.0;
    int axis = f >> 1;
    m = vec3(axis == 0 ? sg : 0.0, axis == 1 ? sg : 0.0, axis == 2 ? sg : 0.0);
    s = axis == 0 ? vec3(0.0, 0.0, -sg) : (axis == 1 ? vec3(1.0, 0.0, 0.0) : vec3(sg, 0.0, 0.0));
    t = axis == 1 ? vec3(0.0, 0.0, sg) : vec3(0.0, -1.0, 0.0);
}

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
    vec3 m, s, t;
    cmoAxes(f, m, s, t);
    vec2 st = vec2(dot(d, s), dot(d, t)) / dot(d, m);
    return ivec3(clamp(ivec2(floor((st * 0.5 + 0.5) * float(n))), ivec2(0), ivec2(n - 1)), f);
}

float cmoDistanceAt(CmoRecord c, ivec3 texel) {
    return texelFetch(cmoDistance, ivec3(texel.xy, int(c.params.x) + texel.z), int(c.params.y)).x;
}

// The parameter at which the ray leaves face f's frustum (it is inside at t): the first of the
// four planes dot(q, M +- S) = 0, dot(q, M +- T) = 0 it crosses going out.
float cmoFaceExit(vec3 o, vec3 r, int f) {
    vec3 m, s, t;
    cmoAxes(f, m, s, t);
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

// The captured surface's distance toward q, bilinear between the four level-0 texel centres
// around q on its face (clamped at the face's edges): a continuous surface where the texels
// are a staircase, to confirm and place a crossing the staircase suggests.
// The face is the caller's (f and its axes m, s, t): the refinement stays on the face it began
// on (clamped at its edge), which keeps the dynamically indexed face tables out of its loop.
float cmoDistanceSmooth(CmoRecord c, int f, vec3 m, vec3 s, vec3 t, vec3 q) {
    int n = int(c.center.w);
    vec2 st = vec2(dot(q, s), dot(q, t)) / max(dot(q, m), 1e-6);
    vec2 x = (st * 0.5 + 0.5) * float(n) - 0.5;
    ivec2 i0 = ivec2(floor(x));
    vec2 w = x - vec2(i0);
    ivec2 a = clamp(i0, ivec2(0), ivec2(n - 1)), b = clamp(i0 + 1, ivec2(0), ivec2(n - 1));
    int layer = int(c.params.x) + f, base = int(c.params.y);
    float d00 = texelFetch(cmoDistance, ivec3(a.x, a.y, layer), base).x;
    float d10 = texelFetch(cmoDistance, ivec3(b.x, a.y, layer), base).x;
    float d01 = texelFetch(cmoDistance, ivec3(a.x, b.y, layer), base).x;
    float d11 = texelFetch(cmoDistance, ivec3(b.x, b.y, layer), base).x;
    // Across a silhouette (neighbours further apart than a surface at 83 degrees to the line of
    // sight steps, 8 texel footprints) no surface joins them: a bilinear sheet there would
    // catch every ray that passes behind the nearer object. The texel's own distance instead.
    float lo = min(min(d00, d10), min(d01, d11)), hi = max(max(d00, d10), max(d01, d11));
    if (hi > lo * (1.0 + 8.0 * c.params.w)) return w.y < 0.5 ? (w.x < 0.5 ? d00 : d10) : (w.x < 0.5 ? d01 : d11);
    return mix(mix(d00, d10, w.x), mix(d01, d11, w.x), w.y);
}

// The refinement step: a crossing the staircase suggests between lo (in front) and hi, on the
// smooth surface. Returns its t (bisection), -1 when the smooth surface has the ray still in
// front at hi (a staircase step, not a crossing: go on), or -2 when the smooth crossing lies
// deeper than the tolerance behind (a silhouette the ray passed behind).
float cmoRefine(CmoRecord c, vec3 o, vec3 r, float lo, float hi, float thickness) {
    vec3 h = o + r * hi;
    int f = cmoFace(h);
    vec3 fm, fs, ft;
    cmoAxes(f, fm, fs, ft);
    if (length(h) <= cmoDistanceSmooth(c, f, fm, fs, ft, h)) return -1.0;
    for (int k = 0; k < 7; ++k) {
        float mid = 0.5 * (lo + hi);
        vec3 q = o + r * mid;
        if (length(q) > cmoDistanceSmooth(c, f, fm, fs, ft, q)) hi = mid;
        else lo = mid;
    }
    h = o + r * hi;
    float d = cmoDistanceSmooth(c, f, fm, fs, ft, h);
    return length(h) - d <= cmoTolerance(c, d, thickness) ? hi : -2.0;
}

// Where a ray that starts on a surface the CMO captured leaves that surface. The CMO knows the
// surface as a staircase of texels: seen at angle theta from its normal, one texel's step is
// d * texelAngle * tan(theta) deep along the line of sight. The ray walks in steps of half the
// footprint at its start (d times the texel angle) and starts where it is in front of the
// staircase by one step (`margin`); while it lies behind by no more than a step plus the
// tolerance it is still on its own surface. Deeper behind, or still not clear after 32 steps,
// the CMO cannot see the start: -1 (unresolved). `n`: the start's surface normal, zero for a
// ray in the open (it starts at once). Seed 000 used one constant bias and found it could not
// be set; this is the per-ray start it asked for, from the distance and the texel's footprint.
float cmoLeaveSurface(CmoRecord c, vec3 o, vec3 r, vec3 n, float tMax, float thickness, inout int iterations) {
    float d0 = max(length(o), 1e-3);
    float cosTheta = abs(dot(n, o)) / d0;
    float tanTheta = min(sqrt(max(1.0 - cosTheta * cosTheta, 0.0)) / max(cosTheta, 0.125), 8.0);
    float margin = dot(n, n) > 0.0 ? d0 * c.params.w * tanTheta : 0.0;
    float step = 0.5 * d0 * c.params.w;
    float t = 0.0;
    for (int k = 0; k < 32; ++k) {
        vec3 q = o + r * t;
        float d = cmoDistanceAt(c, cmoTexel(c, q));
        float behind = length(q) - d;
        if (behind < -margin) return t;
        if (behind > margin + cmoTolerance(c, d, thickness) || t >= tMax) return -1.0;
        t += step;
        ++iterations;
    }
    return -1.0;
}

// Hierarchical trace of o + t r, t in [0, tMax], through CMO c (from where it leaves its start's
// surface, cmoLeaveSurface: n its normal, zero in the open). Returns kCmoHit (tHit set),
// kCmoMiss or kCmoUnresolved; `iterations` counts cells visited (bounded by maxIterations).
// `passBehind`: a ray that passes behind a surface goes on behind it instead of being
// unresolved (seed 000 §3.9's "best candidate": the tracer's last resort when every CMO left the
// ray unresolved; right for thin occluders such as pillars, wrong where the ray meets the
// occluder's unseen back).
int cmoTraceHierarchical(CmoRecord c, vec3 o, vec3 r, vec3 n, float tMax, float thickness, int maxIterations,
                         bool passBehind, inout int iterations, out float tHit) {
    tHit = 0.0;
    int size = int(c.center.w);
    int layer0 = int(c.params.x);
    int base = int(c.params.y);
    int top = int(c.params.z) - 1;
    int level = min(2, top);
    float t = cmoLeaveSurface(c, o, r, n, tMax, thickness, iterations);
    if (t < 0.0) return kCmoUnresolved;
    float tFront = t;
    for (int faces = 0; faces < 4 && t < tMax; ++faces) {
        vec3 q = o + r * t;
        int f = cmoFace(q);
        vec3 M, S, T;
        cmoAxes(f, M, S, T);
        float oM = dot(o, M), oS = dot(o, S), oT = dot(o, T);
        float rM = dot(r, M), rS = dot(r, S), rT = dot(r, T);
        float tFace = min(cmoFaceExit(o, r, f), tMax);
        // The projected ray is a straight line on the face, monotonic in t (seed 000 theorem
        // 3.2): its direction in s and t has a fixed sign over the face.
        float dirS = rS * oM - oS * rM, dirT = rT * oM - oT * rM;
        // The walk stops at a level-0 texel the ray reaches (a candidate); the refinement runs
        // outside the walk's loop (a SIMD CPU driver runs a loop body's every branch for all
        // lanes while any lane needs it), and a staircase step resumes the walk.
        for (;;) {
            bool candidate = false;
            float tb = t;
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
                tb = min(min(ts, tt), tFace);
                float dMin = texelFetch(cmoDistance, ivec3(cell, layer0 + f), base + level).x;
                float rayMax = max(length(q), length(o + r * tb));
                if (rayMax < dMin) {
                    // In front of everything this cell saw: skip it, look wider.
                    t = tb + 1e-5 * (1.0 + tb);
                    tFront = tb;
                    level = min(level + 1, top);
                } else if (level > 0) {
                    --level;
                } else {
                    candidate = true;
                    break;
                }
            }
            if (!candidate) break;
            // Confirmed and placed on the smooth surface from where the ray was last known in
            // front (tFront) to the texel's exit.
            float th = cmoRefine(c, o, r, tFront, tb, thickness);
            if (th >= 0.0) {
                tHit = th;
                return kCmoHit;
            }
            // Behind a surface deeper than the tolerance: unresolved, or with `passBehind` the ray
            // is taken to pass behind it (every surface thinner than the gap) and the walk goes on.
            if (th < -1.5 && !passBehind) return kCmoUnresolved;
            t = tb + 1e-5 * (1.0 + tb);
            tFront = tb;
            level = min(level + 1, top);
        }
        t = tFace + 1e-5 * (1.0 + tFace);
        if (iterations >= maxIterations) return kCmoUnresolved;
    }
    return kCmoMiss;
}

// Constant-step trace: delta at every `step` against the staircase; a sign change is confirmed
// and placed by the same refinement step (cmoRefine) as the hierarchy's.
int cmoTraceLinear(CmoRecord c, vec3 o, vec3 r, vec3 n, float tMax, float step, float thickness, int maxIterations,
                   bool passBehind, inout int iterations, out float tHit) {
    tHit = 0.0;
    float start = cmoLeaveSurface(c, o, r, n, tMax, thickness, iterations);
    if (start < 0.0) return kCmoUnresolved;
    float prev = start, t = start;
    // As the hierarchy's: the loop finds a candidate, the refinement runs outside it.
    for (;;) {
        bool candidate = false;
        while (iterations < maxIterations) {
            ++iterations;
            t = min(prev + step, tMax);
            vec3 q = o + r * t;
            if (length(q) > cmoDistanceAt(c, cmoTexel(c, q))) {
                candidate = true;
                break;
            }
            if (t >= tMax) return kCmoMiss;
            prev = t;
        }
        if (!candidate) return kCmoUnresolved;
        float th = cmoRefine(c, o, r, prev, t, thickness);
        if (th >= 0.0) {
            tHit = th;
            return kCmoHit;
        }
        if (th < -1.5 && !passBehind) return kCmoUnresolved;
        if (t >= tMax) return kCmoMiss;
        prev = t;
    }
    return kCmoUnresolved;
}

#endif
