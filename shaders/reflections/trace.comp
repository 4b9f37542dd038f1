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
#include "reflections/common.glsl"
#include "reflections/material.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;         // rg32f, all levels, texelFetch
layout(set = 0, binding = 2) uniform sampler2D normalTex;   // xyz normal, w roughness
layout(set = 0, binding = 3) uniform sampler2D emissiveTex; // a: flags | material index
layout(set = 0, binding = 5, rgba32f) uniform writeonly image2D hitOut;

struct ScreenRay {
    ivec2 pixel; // the origin's pixel
    vec3 o;      // pixel centre, depth
    vec3 d;      // to the end point: o + d is the far end (t = 1)
    float tMax;  // where it leaves the screen
};

ScreenRay screenRay(vec2 px, float depth, vec3 n) {
    vec3 p = worldAt(px, depth);
    vec3 v = normalize(p - rf.camera.xyz);
    vec3 r = reflect(v, n);
    float z = linearDepth(depth);
    float away = -(mat3(rf.view) * r).z;
    // Rays toward the camera end just before the near plane; others far enough that their end
    // point is the vanishing point to well under a pixel.
    float len = away < -1e-6 ? max((z - 1.5 * rf.camera.w) / -away, 0.0) : 1000.0 * z + 1000.0;
    ScreenRay ray;
    ray.pixel = ivec2(floor(px));
    ray.o = vec3(px, depth);
    ray.d = projectToScreen(p + r * len) - ray.o;
    float tMax = 1.0;
    if (ray.d.x > 0.0) tMax = min(tMax, (rf.size.x - ray.o.x) / ray.d.x);
    if (ray.d.x < 0.0) tMax = min(tMax, -ray.o.x / ray.d.x);
    if (ray.d.y > 0.0) tMax = min(tMax, (rf.size.y - ray.o.y) / ray.d.y);
    if (ray.d.y < 0.0) tMax = min(tMax, -ray.o.y / ray.d.y);
    ray.tMax = max(tMax, 0.0);
    return ray;
}

float occupiedFar(float farthest) {
    return farthest / (1.0 + rf.trace2.x);
}

// The t at which the ray enters the occupied interval [lo, hi] of a cell, within [t0, t1].
float entryT(ScreenRay ray, float lo, float hi, float t0, float t1) {
    float te = ray.d.z < 0.0 ? (hi - ray.o.z) / ray.d.z : ray.d.z > 0.0 ? (lo - ray.o.z) / ray.d.z : t0;
    return clamp(te, t0, t1);
}

// Depth between pixel centres, bilinear in the four nearest samples: exact where the surface is
// planar (depth is affine in screen space). `planar` is false across depth discontinuities.
float surfaceDepth(vec2 pos, out bool planar) {
    vec2 p = pos - 0.5;
    ivec2 i = clamp(ivec2(floor(p)), ivec2(0), ivec2(rf.size.xy) - 2);
    vec2 f = clamp(p - vec2(i), 0.0, 1.0);
    float a = texelFetch(hiz, i, 0).g, b = texelFetch(hiz, i + ivec2(1, 0), 0).g;
    float c = texelFetch(hiz, i + ivec2(0, 1), 0).g, d = texelFetch(hiz, i + ivec2(1, 1), 0).g;
    float lo = min(min(a, b), min(c, d)), hi = max(max(a, b), max(c, d));
    planar = lo > 0.0 && hi <= lo * 1.05;
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

// Sub-pixel hit: a pixel's single depth sample makes a ray that meets a surface at a grazing
// screen-space angle stop up to several pixels early. Where the surface is smooth around the
// hit, bisect the sign change of (ray depth - interpolated surface depth) within 1.5 pixels.
const int kSubPixelSteps = 6;
float refineHit(ScreenRay ray, float t, inout int iterations) {
    float major = max(abs(ray.d.x), abs(ray.d.y));
    float dt = 1.5 / major;
    float a = max(t - dt, 0.0), b = min(t + dt, ray.tMax);
    bool sa, sb;
    float fa = ray.o.z + ray.d.z * a - surfaceDepth(ray.o.xy + ray.d.xy * a, sa);
    float fb = ray.o.z + ray.d.z * b - surfaceDepth(ray.o.xy + ray.d.xy * b, sb);
    // Only rays arriving from in front of a smooth surface (f > 0 in front, f <= 0 behind).
    if (!(sa && sb && fa > 0.0 && fb <= 0.0)) return t;
    for (int k = 0; k < kSubPixelSteps; ++k) {
        float m = 0.5 * (a + b);
        bool sm;
        float fm = ray.o.z + ray.d.z * m - surfaceDepth(ray.o.xy + ray.d.xy * m, sm);
        if (!sm) return t;
        if (fm > 0.0) a = m;
        else b = m;
    }
    iterations += kSubPixelSteps;
    return b;
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

// Returns (t, status, iterations): status 0 hit at t, else the miss code of the hit image.
// The loop only breaks, never returns: lavapipe runs every branch of a loop body for the whole
// vector, so work that belongs after the hit (refinement) must sit outside the loop.
vec3 traceHiZ(ScreenRay ray) {
    ivec2 screen = ivec2(rf.size.xy);
    int maxLevel = int(rf.modes.w) - 1;
    int preSteps = int(rf.trace.y);
    int stopLevel = min(int(rf.trace.w), maxLevel);
    vec2 invD = vec2(ray.d.x != 0.0 ? 1.0 / ray.d.x : 3.0e38, ray.d.y != 0.0 ? 1.0 / ray.d.y : 3.0e38);
    ivec2 pix = ray.pixel;
    int level = 0;
    float t = 0.0;
    int maxIterations = int(rf.trace.x);
    float status = -4.0;
    int it = 0;
    for (; it < maxIterations; ++it) {
        ivec2 levelSize = hizLevelSize(level);
        ivec2 cell = min(pix >> level, levelSize - 1);
        ivec2 cmin = cell << level;
        // Explicit selects: lavapipe mis-evaluates integer mix() with a bvec2 here.
        ivec2 cmax = ivec2(cell.x == levelSize.x - 1 ? screen.x : (cell.x + 1) << level,
                           cell.y == levelSize.y - 1 ? screen.y : (cell.y + 1) << level) - 1;
        vec2 bound = vec2(ray.d.x >= 0.0 ? cmax.x + 1 : cmin.x, ray.d.y >= 0.0 ? cmax.y + 1 : cmin.y);
        vec2 tb = (bound - ray.o.xy) * invD;
        tb = vec2(ray.d.x == 0.0 ? 3.0e38 : tb.x, ray.d.y == 0.0 ? 3.0e38 : tb.y);
        float tExit = min(tb.x, tb.y);
        float tEnd = min(tExit, ray.tMax);
        // Iteration 0 only leaves the start pixel.
        vec2 mm = texelFetch(hiz, cell, level).rg;
        float lo = occupiedFar(mm.x);
        float dA = ray.o.z + ray.d.z * t;
        float dB = ray.o.z + ray.d.z * tEnd;
        if (it > 0 && max(dA, dB) >= lo && min(dA, dB) <= mm.y) {
            // Before the entry point the ray is in front of (or behind) everything in the
            // cell: move there, then look closer (Uludag's intersectDepthPlane).
            t = entryT(ray, lo, mm.y, t, tEnd);
            if (level <= stopLevel) {
                status = 0.0;
                break;
            }
            pix = forward(pix, clamp(ivec2(floor(ray.o.xy + ray.d.xy * t)), cmin, cmax), ray.d.xy);
            --level;
            continue;
        }
        if (tExit >= ray.tMax) {
            status = -2.0;
            break;
        }
        t = tExit;
        vec2 pos = ray.o.xy + ray.d.xy * t;
        ivec2 next = ivec2(ray.d.x >= 0.0 ? cmax.x + 1 : cmin.x - 1, ray.d.y >= 0.0 ? cmax.y + 1 : cmin.y - 1);
        ivec2 along = forward(pix, clamp(ivec2(floor(pos)), cmin, cmax), ray.d.xy);
        pix.x = tb.x <= tb.y ? next.x : along.x;
        pix.y = tb.y <= tb.x ? next.y : along.y;
        if (any(lessThan(pix, ivec2(0))) || any(greaterThanEqual(pix, screen))) {
            status = -3.0;
            break;
        }
        level = it < preSteps ? 0 : it == preSteps ? min(int(rf.trace.z), maxLevel) : min(level + 1, maxLevel);
    }
    return vec3(t, status, float(min(it + 1, maxIterations)));
}

// Linear march: fixed steps along the major axis, a point test per step, then a binary search
// between the last point in front and the first point behind a surface.
// The origin's own pixel never occludes: against its single depth sample, a ray leaving a
// surface that recedes with it reads as behind it, and the refinement would collapse onto the
// origin (a self-hit, seen as dashes along creases).
bool behind(ScreenRay ray, float t, out bool inside) {
    vec2 pos = ray.o.xy + ray.d.xy * t;
    ivec2 p = clamp(ivec2(floor(pos)), ivec2(0), ivec2(rf.size.xy) - 1);
    float scene = texelFetch(hiz, p, 0).g;
    float rayDepth = ray.o.z + ray.d.z * t;
    bool origin = all(equal(p, ray.pixel));
    inside = !origin && rayDepth <= scene && rayDepth >= occupiedFar(scene);
    return !origin && rayDepth <= scene;
}

vec3 traceLinear(ScreenRay ray) {
    float major = max(abs(ray.d.x), abs(ray.d.y));
    if (major <= 0.0) return vec3(0.0, -1.0, 0.0);
    float dt = rf.trace2.y / major;
    int maxSteps = int(rf.trace2.z);
    float status = -1.0;
    int i = 1;
    for (; i <= maxSteps; ++i) {
        float t = float(i) * dt;
        if (t >= ray.tMax) break;
        bool inside;
        behind(ray, t, inside);
        if (inside) {
            status = 0.0;
            break;
        }
    }
    if (status < 0.0) return vec3(0.0, status, float(min(i, maxSteps)));
    float a = float(i - 1) * dt, b = float(i) * dt;
    int refine = int(rf.trace2.w);
    for (int k = 0; k < refine; ++k) {
        float m = 0.5 * (a + b);
        bool unused;
        if (behind(ray, m, unused)) b = m;
        else a = m;
    }
    return vec3(b, 0.0, float(i + refine));
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, ivec2(rf.size.xy)))) return;
    vec4 result = vec4(-1.0, -1.0, -1.0, 0.0);
    float depth = texelFetch(hiz, pixel, 0).g;
    vec4 normalRough = texelFetch(normalTex, pixel, 0);
    PixelMaterial m = pixelMaterial(texelFetch(emissiveTex, pixel, 0).a, normalRough.w);
    if (depth > 0.0 && m.reflective && m.screenSpace && m.roughness <= m.maxScreenSpace) {
        ScreenRay ray = screenRay(vec2(pixel) + 0.5, depth, normalize(normalRough.xyz));
        if (ray.tMax > 0.0 && finite3(ray.d)) {
            vec3 r = rf.modes.x == 0u ? traceHiZ(ray) : traceLinear(ray);
            result = r.y == 0.0 ? hitAt(ray, r.x, int(r.z)) : vec4(-1.0, -1.0, r.y, r.z);
        }
    }
    imageStore(hitOut, pixel, result);
}
