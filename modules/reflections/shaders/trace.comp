#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.trace: one mirror ray per reflective pixel through the depth buffer, by Hi-Z
// min/max traversal (default) or by the linear march with binary refinement (the baseline).
// Writes the hit's screen position and depth and the iterations spent.
//
// Hi-Z traversal (Uludag 4.4.3, min/max as in 4.6.6-4.6.7): the ray is a segment in screen
// space (pixels, reversed-Z depth). In a cell of level L it tests its depth interval over the
// cell against the cell's occupied interval [farthest / (1 + thickness), closest]: no overlap
// means empty space, so it jumps to the cell's exit and goes up a level; an overlap means
// descend, and at the stop level it is a hit. Rays toward the camera and rays passing behind
// surfaces need no special case: both are interval tests. Two fixes against resolution-
// dependent stripes: the origin is the pixel centre with its own depth sample, and cells are
// crossed per axis in integer pixel coordinates (no epsilon nudges that vanish at some sizes).
#include "common/brdf.glsl"
#include "reflections/shaders/common.glsl"
#include "reflections/shaders/material.glsl"
#include "reflections/shaders/stochastic.glsl"
#define PLANAR_BUFFER_BINDING 16
#define PLANAR_IMAGES_BINDING 17
#include "probes/shaders/planar.glsl"
#include "reflections/shaders/chain.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;         // rg32f, all levels, texelFetch
layout(set = 0, binding = 2) uniform sampler2D normalTex;   // xyz normal, w roughness
layout(set = 0, binding = 3) uniform sampler2D emissiveTex; // a: flags | material index
layout(set = 0, binding = 5, rgba32f) uniform writeonly image2D hitOut;
#include "reflections/shaders/mirror_hit.glsl"  // the CMO list's second bounces
// reflections.trace (TraceMode: 0 hiz, 1 linear) as a specialization constant: lavapipe would
// otherwise run the other tracer's loops once per pixel too.
layout(constant_id = 0) const uint kTraceMode = 0u;
// reflections.resolution (1: half): each invocation traces the full-resolution pixel of its 2x2
// that reflections.classify chose (the guide, reflections/guide.glsl) and writes the hit at its
// own half-resolution position.
layout(constant_id = 1) const uint kHalf = 0u;
layout(set = 0, binding = 6) uniform sampler2D guideTex;  // half only
// Tile lists (reflections.classify): the work list traces, the fill list writes "not traced". The
// work list's tiles then go to the CMO trace's lists by what screen space left uncovered.
#define SPECULUM_TILES_WRITE
#include "reflections/shaders/tiles.glsl"
shared uint needsCmo;
// reflections.glossy (1: stochastic): glossy pixels trace a GGX visible-normal sample
// (reflections/stochastic.glsl) instead of the mirror ray.
layout(constant_id = 2) const uint kStochastic = 0u;

struct ScreenRay {
    ivec2 pixel; // the origin's pixel
    vec3 o;      // pixel centre, depth
    vec3 d;      // to the end point: o + d is the far end (t = 1)
    float tMax;  // where it leaves the screen or reaches distanceFadeEnd(), whichever is first
    bool faded;  // tMax is the distance fade's, not the screen edge
};

// The mirror ray r from world point p, seen at pixel centre px with depth `depth`.
ScreenRay screenRay(vec2 px, float depth, vec3 p, vec3 r) {
    float z = linearDepth(depth);
    float away = -(mat3(rfm.view) * r).z;
    // Rays toward the camera end just before the near plane; others far enough that their end
    // point is the vanishing point to well under a pixel.
    float len = away < -1e-6 ? max((z - 1.5 * rfm.znear) / -away, 0.0) : 1000.0 * z + 1000.0;
    ScreenRay ray;
    ray.pixel = ivec2(floor(px));
    ray.o = vec3(px, depth);
    ray.d = projectToScreen(p + r * len) - ray.o;
    float tMax = 1.0;
    if (ray.d.x > 0.0) tMax = min(tMax, (rf.size.x - ray.o.x) / ray.d.x);
    if (ray.d.x < 0.0) tMax = min(tMax, -ray.o.x / ray.d.x);
    if (ray.d.y > 0.0) tMax = min(tMax, (rf.size.y - ray.o.y) / ray.d.y);
    if (ray.d.y < 0.0) tMax = min(tMax, -ray.o.y / ray.d.y);
    // Past distanceFadeEnd() a hit weighs nothing: the ray ends there. The screen point of that
    // world point lies on the ray's line; its t is the projection onto d.
    float fadeEnd = distanceFadeEnd();
    float tFade = 2.0;
    if (fadeEnd < len) {
        vec2 q = projectToScreen(p + r * fadeEnd).xy - ray.o.xy;
        tFade = dot(q, ray.d.xy) / max(dot(ray.d.xy, ray.d.xy), 1e-30);
    }
    ray.faded = tFade < tMax;
    ray.tMax = max(min(tMax, tFade), 0.0);
    return ray;
}

// A surface occupies depths [farthest * occupiedFarScale(), closest] (the thickness model).
// Callers take it once per ray: a division per cell test or step costs a CPU driver 3%.
float occupiedFarScale() {
    return 1.0 / (1.0 + rf.thickness);
}

// The t at which the ray enters the occupied interval [lo, hi] of a cell, within [t0, t1].
float entryT(ScreenRay ray, float invDz, float lo, float hi, float t0, float t1) {
    float te = ray.d.z < 0.0 ? (hi - ray.o.z) * invDz : ray.d.z > 0.0 ? (lo - ray.o.z) * invDz : t0;
    return clamp(te, t0, t1);
}

// Depth between pixel centres, bilinear in the four nearest samples: exact where the surface is
// planar (depth is affine in screen space). `planar` is false across depth discontinuities.
float surfaceDepth(vec2 pos, out bool planar) {
    vec2 p = pos - 0.5;
    ivec2 i = clamp(ivec2(floor(p)), ivec2(0), ivec2(rf.size.xy) - 2);
    vec2 f = clamp(p - vec2(i), 0.0, 1.0);
    // One gather of the 2x2 block (its corner is the shared texel corner i + 1): x (i, j+1),
    // y (i+1, j+1), z (i+1, j), w (i, j). Cheaper on lavapipe than four texelFetch: the
    // trace at 960x540 with one iteration (its fixed cost) went from 36 to 32 ms.
    vec4 q = textureGather(hiz, (vec2(i) + 1.0) * rf.size.zw, 1);
    float a = q.w, b = q.z, c = q.x, d = q.y;
    float lo = min(min(a, b), min(c, d)), hi = max(max(a, b), max(c, d));
    planar = lo > 0.0 && hi <= lo * 1.05;
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

// Sub-pixel hit: a pixel's single depth sample makes a ray that meets a surface at a grazing
// screen-space angle stop up to several pixels early. Where the surface is smooth around the
// hit, find the sign change of f = (ray depth - interpolated surface depth) near t by false
// position (Illinois): on a plane f is affine along the ray (depth is affine in screen space
// and bilinear interpolation of affine samples is exact), so one step is exact there and a
// second only corrects curved surfaces. (Bisection needed 6 steps for 1/20 pixel.)
const int kSubPixelSteps = 2;
// How far past the bracket a grazing hit's root may be sought, in pixels. Rays that meet a
// floor at a shallow screen-space angle fire the point test 2-4 pixels early.
const float kGrazingReach = 8.0;

float rayMinusSurface(ScreenRay ray, float t, out bool planar) {
    return ray.o.z + ray.d.z * t - surfaceDepth(ray.o.xy + ray.d.xy * t, planar);
}

float refineHit(ScreenRay ray, float t, inout int iterations) {
    float major = max(abs(ray.d.x), abs(ray.d.y));
    float dt = 1.5 / major;
    float a = max(t - dt, 0.0), b = min(t + dt, ray.tMax);
    bool sa, sb;
    float fa = rayMinusSurface(ray, a, sa);
    float fb = rayMinusSurface(ray, b, sb);
    if (sa && sb && fa > fb && fb > 0.0) {
        // Still in front at b but closing in: extrapolate f (affine on a plane) to its root,
        // a quarter pixel past it so that a plane's root is bracketed.
        float c = b + fb * (b - a) / (fa - fb) + 0.25 / major;
        c = min(c, min(b + kGrazingReach / major, ray.tMax));
        a = b;
        fa = fb;
        b = c;
        fb = rayMinusSurface(ray, b, sb);
        iterations += 1;
    }
    // Only rays arriving from in front of a smooth surface (f > 0 in front, f <= 0 behind).
    if (!(sa && sb && fa > 0.0 && fb <= 0.0)) return t;
    // A residual this small puts the root within about 1/50 pixel (f's slope is at least
    // (fa - fb) / 3 pixels on a plane): planar hits stop after one step.
    float tolerance = (fa - fb) * (0.02 / 3.0);
    float side = 0.0;  // the side kept last: -1 a, +1 b
    int k = 0;
    for (; k < kSubPixelSteps; ++k) {
        float m = (a * fb - b * fa) / (fb - fa);
        bool sm;
        float fm = rayMinusSurface(ray, m, sm);
        if (!sm) return t;
        if (abs(fm) <= tolerance) {
            a = b = m;
            break;
        }
        if (fm > 0.0) {
            a = m;
            fa = fm;
            if (side < 0.0) fb *= 0.5;  // Illinois: halve the stale end's weight
            side = -1.0;
        } else {
            b = m;
            fb = fm;
            if (side > 0.0) fa *= 0.5;
            side = 1.0;
        }
    }
    iterations += min(k + 1, kSubPixelSteps);
    return a == b ? a : (a * fb - b * fa) / (fb - fa);
}

vec4 hitAt(ScreenRay ray, float t, int iterations) {
    t = refineHit(ray, t, iterations);
    return vec4(ray.o.xy + ray.d.xy * t, ray.o.z + ray.d.z * t, float(iterations));
}

// The pixel under the ray only moves forward along each axis. A point exactly on a cell
// boundary floors into the cell just left; without this the traversal could step back into it
// and cycle between two levels until out of iterations.
ivec2 forward(ivec2 current, ivec2 candidate, vec2 dir) {
    return ivec2(dir.x >= 0.0 ? max(current.x, candidate.x) : min(current.x, candidate.x),
                 dir.y >= 0.0 ? max(current.y, candidate.y) : min(current.y, candidate.y));
}

// A cell of the Hi-Z level under a pixel, in level-0 pixels, and where the ray leaves it.
struct Cell {
    ivec2 index;  // in its level
    ivec2 lo, hi; // first and last pixel covered (the last row and column reach the screen edge)
    vec2 tb;      // t at the exit boundary per axis
    float tExit;
};

Cell cellAt(ScreenRay ray, vec2 invD, ivec2 pix, int level) {
    ivec2 screen = ivec2(rf.size.xy);
    ivec2 levelSize = hizLevelSize(level);
    Cell c;
    c.index = min(pix >> level, levelSize - 1);
    c.lo = c.index << level;
    // Explicit selects: lavapipe mis-evaluates integer mix() with a bvec2 here.
    c.hi = ivec2(c.index.x == levelSize.x - 1 ? screen.x : (c.index.x + 1) << level,
                 c.index.y == levelSize.y - 1 ? screen.y : (c.index.y + 1) << level) - 1;
    vec2 bound = vec2(ray.d.x >= 0.0 ? c.hi.x + 1 : c.lo.x, ray.d.y >= 0.0 ? c.hi.y + 1 : c.lo.y);
    c.tb = (bound - ray.o.xy) * invD;
    c.tExit = min(c.tb.x, c.tb.y);
    return c;
}

// The pixel under the ray at t, kept in the cell and never stepping back.
ivec2 pixelAt(ScreenRay ray, Cell c, ivec2 pix, float t) {
    return forward(pix, clamp(ivec2(floor(ray.o.xy + ray.d.xy * t)), c.lo, c.hi), ray.d.xy);
}

// Past the cell's exit, crossed per axis in integers (the stripe fix): the axis whose boundary
// comes first steps into the next cell, the other keeps `atExit` (pixelAt the exit).
ivec2 crossExit(ScreenRay ray, Cell c, ivec2 atExit) {
    ivec2 next = ivec2(ray.d.x >= 0.0 ? c.hi.x + 1 : c.lo.x - 1, ray.d.y >= 0.0 ? c.hi.y + 1 : c.lo.y - 1);
    return ivec2(c.tb.x <= c.tb.y ? next.x : atExit.x, c.tb.y <= c.tb.x ? next.y : atExit.y);
}

bool offScreen(ivec2 pix) {
    return any(lessThan(pix, ivec2(0))) || any(greaterThanEqual(pix, ivec2(rf.size.xy)));
}

// Returns (t, status, iterations): status 0 hit at t, else the miss code of the hit image:
// -1 not traced, -2 reached tMax (main: -5 when that is the distance fade's end), -3 crossed
// off screen, -4 out of iterations.
// An iteration is one cell test (one Hi-Z fetch); leaving the origin's pixel is set-up, as in
// Uludag's listing. The loop only breaks, never returns: lavapipe runs every branch of a loop
// body for the whole vector, so work that belongs after the hit (refinement) sits outside it.
vec3 traceHiZ(ScreenRay ray) {
    int maxLevel = int(rf.hizLevels) - 1;
    int preSteps = int(rf.linearPreSteps);
    int stopLevel = min(int(rf.hizStopLevel), maxLevel);
    // Finite for axes the ray does not move along: their exit t is then far past tMax.
    vec2 invD = vec2(ray.d.x != 0.0 ? 1.0 / ray.d.x : 3.0e38, ray.d.y != 0.0 ? 1.0 / ray.d.y : 3.0e38);
    float invDz = ray.d.z != 0.0 ? 1.0 / ray.d.z : 0.0;
    float farScale = occupiedFarScale();
    Cell origin = cellAt(ray, invD, ray.pixel, 0);
    if (origin.tExit >= ray.tMax) return vec3(0.0, -2.0, 0.0);
    ivec2 pix = crossExit(ray, origin, pixelAt(ray, origin, ray.pixel, origin.tExit));
    if (offScreen(pix)) return vec3(0.0, -3.0, 0.0);
    float t = origin.tExit;
    int level = preSteps > 0 ? 0 : min(int(rf.hizStartLevel), maxLevel);
    int maxIterations = int(rf.maxIterations);
    float status = -4.0;
    // Up only into a parent the ray crosses whole along its major axis (it enters at the
    // parent's first child that way): a parent entered half-way spans children beside the rest
    // of the path whose closest depth reads as an overlap (a floor's nearer rows under a grazing
    // ray), and the one child left costs a single test at this level.
    bool xMajor = abs(ray.d.x) >= abs(ray.d.y);
    int firstChildBit = (xMajor ? ray.d.x : ray.d.y) >= 0.0 ? 0 : 1;
    int it = 0;
    for (; it < maxIterations; ++it) {
        Cell c = cellAt(ray, invD, pix, level);
        float tEnd = min(c.tExit, ray.tMax);
        vec2 mm = texelFetch(hiz, c.index, level).rg;
        float lo = mm.x * farScale;
        float dA = ray.o.z + ray.d.z * t;
        float dB = ray.o.z + ray.d.z * tEnd;
        // One straight path for both outcomes (lavapipe would run both sides of an if):
        // an overlap moves to the entry point, before which the ray is in front of (or behind)
        // everything in the cell (Uludag's intersectDepthPlane), and looks closer; an empty
        // cell moves to its exit and crosses into the next cell on the axis that exits first.
        bool overlap = max(dA, dB) >= lo && min(dA, dB) <= mm.y;
        t = overlap ? entryT(ray, invDz, lo, mm.y, t, tEnd) : c.tExit;
        if (overlap && level <= stopLevel) {
            status = 0.0;
            break;
        }
        if (!overlap && c.tExit >= ray.tMax) {
            status = -2.0;
            break;
        }
        ivec2 at = pixelAt(ray, c, pix, t);
        pix = overlap ? at : crossExit(ray, c, at);
        if (offScreen(pix)) {
            status = -3.0;
            break;
        }
        bool firstChild = (((xMajor ? pix.x : pix.y) >> level) & 1) == firstChildBit;
        level = overlap ? level - 1
              : it + 1 < preSteps ? 0
              : it + 1 == preSteps ? min(int(rf.hizStartLevel), maxLevel)
              : firstChild ? min(level + 1, maxLevel) : level;
    }
    return vec3(t, status, float(min(it + 1, maxIterations)));
}

// Linear march: fixed steps along the major axis, a point test per step, then a binary search
// between the last point in front and the first point behind a surface.
// The origin's own pixel never occludes: against its single depth sample, a ray leaving a
// surface that recedes with it reads as behind it, and the refinement would collapse onto the
// origin (a self-hit, seen as dashes along creases).
bool behind(ScreenRay ray, float farScale, float t, out bool inside) {
    vec2 pos = ray.o.xy + ray.d.xy * t;
    ivec2 p = clamp(ivec2(floor(pos)), ivec2(0), ivec2(rf.size.xy) - 1);
    float scene = texelFetch(hiz, p, 0).g;
    float rayDepth = ray.o.z + ray.d.z * t;
    bool origin = all(equal(p, ray.pixel));
    inside = !origin && rayDepth <= scene && rayDepth >= scene * farScale;
    return !origin && rayDepth <= scene;
}

vec3 traceLinear(ScreenRay ray) {
    float major = max(abs(ray.d.x), abs(ray.d.y));
    if (major <= 0.0) return vec3(0.0, -1.0, 0.0);
    float dt = rf.linearStride / major;
    float farScale = occupiedFarScale();
    int maxSteps = int(rf.linearMaxSteps);
    float status = -1.0;
    int i = 1;
    for (; i <= maxSteps; ++i) {
        float t = float(i) * dt;
        if (t >= ray.tMax) break;
        bool inside;
        behind(ray, farScale, t, inside);
        if (inside) {
            status = 0.0;
            break;
        }
    }
    if (status < 0.0) return vec3(0.0, status, float(min(i, maxSteps)));
    float a = float(i - 1) * dt, b = float(i) * dt;
    int refine = int(rf.refineSteps);
    for (int k = 0; k < refine; ++k) {
        float m = 0.5 * (a + b);
        bool unused;
        if (behind(ray, farScale, m, unused)) b = m;
        else a = m;
    }
    return vec3(b, 0.0, float(i + refine));
}

void main() {
    // With tiles, the tiles without a ray keep reflections.trace_clear's "not traced" (the value
    // below).
    ivec2 out_ = tilePixel(kListTrace);
    bool inside = all(lessThan(out_, (ivec2(rf.size.xy) + int(kHalf)) >> kHalf));
    vec4 result = vec4(-1.0, -1.0, -1.0, 0.0);
    if (kTileMode == kTileModeWork && gl_LocalInvocationIndex == 0u) needsCmo = 0u;
    bool cmo = false;
    if (inside) {
        ivec2 pixel = kHalf != 0u ? guidePixel(out_, texelFetch(guideTex, out_, 0)) : out_;
        float depth = texelFetch(hiz, pixel, 0).g;
        vec4 normalRough = texelFetch(normalTex, pixel, 0);
        float flags = texelFetch(emissiveTex, pixel, 0).a;
        PixelMaterial m = pixelMaterial(flags, normalRough.w);
        vec2 px = vec2(pixel) + 0.5;
        vec3 p = worldAt(px, depth);
        vec3 v = normalize(p - rfm.eye);
        vec3 n = normalize(normalRough.xyz);
        vec3 mirror = reflect(v, n);
        vec3 r = kStochastic != 0u ? stochasticDirection(pixel, v, n, m.roughness) : mirror;
        // Rays the camera fade zeroes are not traced (the resolve would weigh their hits by 0), nor
        // those of pixels a planar probe serves (its mirrored image takes them whole).
        bool visible = cameraFade(dot(r, v)) > 0.0;
        bool planar = planarServes(depth, m, p, n);
        if (depth > 0.0 && m.reflective && m.screenSpace && m.roughness <= m.maxScreenSpace && visible && !planar) {
            ScreenRay ray = screenRay(px, depth, p, r);
            if (ray.tMax > 0.0 && finite3(ray.d)) {
                vec3 traced = kTraceMode == 0u ? traceHiZ(ray) : traceLinear(ray);
                float miss = traced.y == -2.0 && ray.faded ? -5.0 : traced.y;
                result = traced.y == 0.0 ? hitAt(ray, traced.x, int(traced.z)) : vec4(-1.0, -1.0, miss, traced.z);
            }
        }
        imageStore(hitOut, out_, result);
        bool covered = screenCovers(result, p, mirror, v, m);
        MirrorHit h;
        cmo = (inCmoBand(depth, m, planar) && !covered) || secondBounceInCmos(covered, px, result, p, m.roughness, false, h);
    }
    if (kTileMode != kTileModeWork) return;
    // The tile's CMO list (cmo_trace.comp runs the same test per pixel).
    barrier();
    if (cmo) atomicOr(needsCmo, 1u);
    barrier();
    if (gl_LocalInvocationIndex == 0u && needsCmo != 0u) {
        uint i = atomicAdd(tiles.args[kListCmo].x, 1u);
        tiles.entries[i * kTileLists + kListCmo] = tiles.entries[gl_WorkGroupID.x * kTileLists + kListTrace];
    }
}
