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
// probes.cmo_store writes SPECULUM_CMO_SKY_DISTANCE (cmo.h) where a face saw the sky: a distance
// above half of it is no surface.
const float kCmoSky = 0.5 * SPECULUM_CMO_SKY_DISTANCE;

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

// Where q falls among the level-0 texel centres of face f (axes m, s, t): the lower-left centre
// i0 of the four around it and the weights w toward the upper-right.
void cmoBilinear(CmoRecord c, vec3 m, vec3 s, vec3 t, vec3 q, out ivec2 i0, out vec2 w) {
    vec2 st = vec2(dot(q, s), dot(q, t)) / max(dot(q, m), 1e-6);
    vec2 x = (st * 0.5 + 0.5) * c.center.w - 0.5;
    i0 = ivec2(floor(x));
    w = x - vec2(i0);
}

// The captured surface from four texel distances around a point (weights w): bilinear where they
// belong to one surface, the nearest texel's across a silhouette (neighbours further apart than a
// surface at 83 degrees to the line of sight steps, 8 texel footprints): no surface joins them
// there, and a bilinear sheet would catch every ray that passes behind the nearer object.
// `skyEdge`: the four straddle a silhouette against the sky, the edge of an opening (a wall's
// end at a window, the open side of a box), which the nearest texel places anywhere within half
// a texel of where it is.
float cmoSmooth(CmoRecord c, float d00, float d10, float d01, float d11, vec2 w, out bool skyEdge) {
    float lo = min(min(d00, d10), min(d01, d11)), hi = max(max(d00, d10), max(d01, d11));
    bool silhouette = hi > lo * (1.0 + 8.0 * c.params.w);
    skyEdge = silhouette && hi >= kCmoSky;
    if (silhouette) return w.y < 0.5 ? (w.x < 0.5 ? d00 : d10) : (w.x < 0.5 ? d01 : d11);
    return mix(mix(d00, d10, w.x), mix(d01, d11, w.x), w.y);
}

// The captured surface's distance toward q, bilinear between the four level-0 texel centres
// around q on its face (clamped at the face's edges): a continuous surface where the texels
// are a staircase, to confirm and place a crossing the staircase suggests.
// The face is the caller's (f and its axes m, s, t): the refinement stays on the face it began
// on (clamped at its edge), which keeps the dynamically indexed face tables out of its loop.
float cmoDistanceSmooth(CmoRecord c, int f, vec3 m, vec3 s, vec3 t, vec3 q, out bool skyEdge) {
    ivec2 i0;
    vec2 w;
    cmoBilinear(c, m, s, t, q, i0, w);
    int n = int(c.center.w);
    ivec2 a = clamp(i0, ivec2(0), ivec2(n - 1)), b = clamp(i0 + 1, ivec2(0), ivec2(n - 1));
    int layer = int(c.params.x) + f, base = int(c.params.y);
    float d00 = texelFetch(cmoDistance, ivec3(a.x, a.y, layer), base).x;
    float d10 = texelFetch(cmoDistance, ivec3(b.x, a.y, layer), base).x;
    float d01 = texelFetch(cmoDistance, ivec3(a.x, b.y, layer), base).x;
    float d11 = texelFetch(cmoDistance, ivec3(b.x, b.y, layer), base).x;
    return cmoSmooth(c, d00, d10, d01, d11, w, skyEdge);
}

// The 3x3 level-0 texels around one texel (clamped at the face's edges, as cmoDistanceSmooth
// clamps): every point inside that texel has its four bilinear neighbours among them. A
// refinement inside one texel reads its nine distances once instead of four per evaluation.
// Rows in y, each vec3 in x from `first` (the texel less one), not an array: an array indexed
// per lane goes to memory on a SIMD CPU driver (STYLE.md).
struct CmoWindow {
    ivec2 first;
    vec3 row0, row1, row2;
};

CmoWindow cmoWindowAround(CmoRecord c, int f, ivec2 texel) {
    int n = int(c.center.w);
    int layer = int(c.params.x) + f, base = int(c.params.y);
    CmoWindow win;
    win.first = texel - 1;
    ivec3 x = clamp(ivec3(texel.x - 1, texel.x, texel.x + 1), ivec3(0), ivec3(n - 1));
    ivec3 y = clamp(ivec3(texel.y - 1, texel.y, texel.y + 1), ivec3(0), ivec3(n - 1));
    win.row0 = vec3(texelFetch(cmoDistance, ivec3(x.x, y.x, layer), base).x,
                    texelFetch(cmoDistance, ivec3(x.y, y.x, layer), base).x,
                    texelFetch(cmoDistance, ivec3(x.z, y.x, layer), base).x);
    win.row1 = vec3(texelFetch(cmoDistance, ivec3(x.x, y.y, layer), base).x,
                    texelFetch(cmoDistance, ivec3(x.y, y.y, layer), base).x,
                    texelFetch(cmoDistance, ivec3(x.z, y.y, layer), base).x);
    win.row2 = vec3(texelFetch(cmoDistance, ivec3(x.x, y.z, layer), base).x,
                    texelFetch(cmoDistance, ivec3(x.y, y.z, layer), base).x,
                    texelFetch(cmoDistance, ivec3(x.z, y.z, layer), base).x);
    return win;
}

float cmoPick(vec3 v, int k) {
    return k <= 0 ? v.x : (k == 1 ? v.y : v.z);
}

// cmoDistanceSmooth's value from the window, for q inside (or within half a texel of) the
// window's middle texel; further out the window's edge texels stand in (the clamp).
float cmoDistanceWindow(CmoRecord c, CmoWindow win, vec3 m, vec3 s, vec3 t, vec3 q, out bool skyEdge) {
    ivec2 i0;
    vec2 w;
    cmoBilinear(c, m, s, t, q, i0, w);
    ivec2 a = clamp(i0 - win.first, ivec2(0), ivec2(2)), b = clamp(i0 + 1 - win.first, ivec2(0), ivec2(2));
    vec3 ra = a.y <= 0 ? win.row0 : (a.y == 1 ? win.row1 : win.row2);
    vec3 rb = b.y <= 0 ? win.row0 : (b.y == 1 ? win.row1 : win.row2);
    return cmoSmooth(c, cmoPick(ra, a.x), cmoPick(ra, b.x), cmoPick(rb, a.x), cmoPick(rb, b.x), w, skyEdge);
}

// The refinement step: a crossing the staircase suggests between lo (in front) and hi, on the
// smooth surface. Returns its t (bisection), -1 when the smooth surface has the ray still in
// front at hi (a staircase step, not a crossing: go on), or -2 when the smooth crossing lies
// deeper than the tolerance behind (a silhouette the ray passed behind), or at the edge of an
// opening (see below).
// The edge of an opening: the ray reached the surface from where the CMO saw the sky (lo's
// texel is sky, or the ray entered lo's texel already behind from a sky texel), or the crossing
// lies in a cell that straddles the sky (cmoSmooth's skyEdge). A wall's end has nothing behind
// it, and the nearest texel puts that end anywhere within half a texel: a ray that leaves a
// room through its open side past the wall's end read as a hit on the wall (cornell_mirrors'
// concave mirror showed the red wall in 130 rim pixels with one CMO where the open side's grey
// is; the view lost 0.65 dB to that CMO, 0.15 with this rule). Unresolved, the ray goes down the
// chain. A silhouette against another surface keeps the tolerance: behind an object's limb its
// unseen side goes on (the knot's tube, the blob's lobes), and refusing those hits cost
// sphere_close and blob_close 0.4-0.5 dB (MEASUREMENTS.md, 2026-12-07).
// Five halvings (1/32 of the bracket) and the smooth distance kept from the step that last set
// hi: six evaluations where seven halvings and a separate final evaluation took nine. Regula
// falsi (Illinois) with three steps was tried too and lost 0.06-0.19 dB on four views: across a
// reflected silhouette the distance jumps, and the secant places the crossing inside the jump
// where the bisection finds its edge (reflections MEASUREMENTS.md, 2026-12-07).
// `inTexel`: the bracket lies in one level-0 texel (the hierarchical walk's candidates), so the
// evaluations read the 3x3 window around the texel of the bracket's middle (9 fetches, not 24;
// not hi's texel: hi is the cell's exit, on the edge of the next one); the linear march's
// bracket is a world step long and reads each evaluation's own four.
float cmoRefine(CmoRecord c, vec3 o, vec3 r, float lo, float hi, float thickness, bool inTexel) {
    vec3 h = o + r * hi;
    int f = cmoFace(h);
    vec3 fm, fs, ft;
    cmoAxes(f, fm, fs, ft);
    CmoWindow win;
    if (inTexel) {
        ivec2 i0;
        vec2 w;
        cmoBilinear(c, fm, fs, ft, o + r * (0.5 * (lo + hi)), i0, w);
        win = cmoWindowAround(c, f, clamp(i0 + ivec2(greaterThanEqual(w, vec2(0.5))), ivec2(0), ivec2(int(c.center.w) - 1)));
    }
    bool edgeHi, edge;
    float dHi = inTexel ? cmoDistanceWindow(c, win, fm, fs, ft, h, edgeHi) : cmoDistanceSmooth(c, f, fm, fs, ft, h, edgeHi);
    float lenHi = length(h);
    if (lenHi <= dHi) return -1.0;
    vec3 ql = o + r * lo;
    float dLo = inTexel ? cmoDistanceWindow(c, win, fm, fs, ft, ql, edge) : cmoDistanceSmooth(c, f, fm, fs, ft, ql, edge);
    float dBefore = cmoDistanceAt(c, cmoTexel(c, o + r * (lo - 1e-4 * (1.0 + lo))));
    bool opening = length(ql) > dLo && dBefore >= kCmoSky;
    for (int k = 0; k < 5; ++k) {
        float mid = 0.5 * (lo + hi);
        vec3 q = o + r * mid;
        float d = inTexel ? cmoDistanceWindow(c, win, fm, fs, ft, q, edge) : cmoDistanceSmooth(c, f, fm, fs, ft, q, edge);
        float len = length(q);
        bool behind = len > d;
        hi = behind ? mid : hi;
        dHi = behind ? d : dHi;
        lenHi = behind ? len : lenHi;
        edgeHi = behind ? edge : edgeHi;
        lo = behind ? lo : mid;
        dLo = behind ? dLo : d;
    }
    opening = opening || dLo >= kCmoSky || edgeHi;
    return !opening && lenHi - dHi <= cmoTolerance(c, dHi, thickness) ? hi : -2.0;
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
            float th = cmoRefine(c, o, r, tFront, tb, thickness, true);
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
        float th = cmoRefine(c, o, r, prev, t, thickness, false);
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
