// Local cubemap probes in a shader (modules/probes): the shader-visible record, declared once
// (probes/shaders/probe.h, shared with C++), and
// the fallback chain's probe step: per pixel, probes in priority order (the buffer is sorted by
// order, then by smallest volume) are blended by their influence weights until the weight
// reaches 1; the caller gives the rest to the sky. Before including, define
// PROBES_BUFFER_BINDING and PROBES_CUBES_BINDING (set 0), and PROBES_DISTANCE_BINDING for the
// captured distances (probeSurfaceT; without it, the proxy alone: the debug views and the
// proxy's own GPU test).
#ifndef SPECULUM_PROBES_GLSL
#define SPECULUM_PROBES_GLSL

#include "common/brdf.glsl"  // F_Schlick
#include "probes/shaders/probe.h"

layout(set = 0, binding = PROBES_BUFFER_BINDING, std430) readonly buffer ProbeBuffer {
    Probe probes[];
};
layout(set = 0, binding = PROBES_CUBES_BINDING) uniform samplerCubeArray probeCubes;
#ifdef PROBES_DISTANCE_BINDING
layout(set = 0, binding = PROBES_DISTANCE_BINDING) uniform samplerCubeArray probeDistance;  // nearest
#endif

// Lobes narrower than probe.h's kNarrowLobeMaxRoughness find their hit on the captured
// distances (probeSurfaceT). An includer whose pixels all have wider lobes (reflections.resolve
// on its rough lookup tiles) defines PROBES_NARROW_LOBES as false, a specialization constant's
// test, to compile that march out: lavapipe runs both sides of every branch.
#ifndef PROBES_NARROW_LOBES
#define PROBES_NARROW_LOBES true
#endif
#ifdef PROBES_DISTANCE_BINDING
// Whether a hit on a captured mirror reflects again (sampleProbes). Only in the main view's
// chain: a capture's surfaces are already a reflection deep, and a further bounce there went past
// the reference's (--bounces 2: gallery.main's planar floor 22.63 -> 22.02 dB).
#ifdef PROBES_CAPTURE
const bool kProbeMirrorHits = false;
const bool kProbeHiddenAlongRay = false;
#else
const bool kProbeMirrorHits = true;
// Whether a ray whose proxy point the capture point cannot see (probeSurfaceT's `hidden`) reads
// the cube along its own direction, as a probe without parallax correction does, instead of at
// the proxy point, where the cube holds whatever hid it. failure_cases' floor showed its overhead
// strip 4 px off where its rays pass behind the strip to the sky (the captured strip hid the
// proxy point); the chrome objects' undersides in cornell_mirrors showed themselves. Mirror
// band: failure_cases 17.99 -> 19.13, concave_close 30.98 -> 32.46, blob_close 20.46 -> 20.81,
// the suite's mean 22.04 -> 22.40 dB (modules/probes/MEASUREMENTS.md, 2026-12-07). Only in the
// main view's chain: in the captures it cost blob_close's rough band 0.8 dB.
const bool kProbeHiddenAlongRay = true;
#endif
// And only for mirrors' lobes: the direction is a guess, which a glossy lobe seen at a grazing
// angle gets badly wrong (gallery.floor_grazing's 0.3 floor band, probes alone: rough band
// 18.98 -> 18.25 dB without this bound).
const float kProbeHiddenMaxRoughness = 0.05;
#endif

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

#ifdef PROBES_DISTANCE_BINDING
// How far q (from the capture point) lies behind what the capture point saw toward it: < 0 in
// front of the captured surface, > 0 behind it (the sky is 65504 m away: always in front).
float probeBehind(Probe pr, vec3 q) {
    return length(q) - textureLod(probeDistance, vec4(q, pr.params.x), 0.0).r;
}

// What counts as on the captured surface at distance len: 3% (about three 128^2 texels' width
// of slant) and 2 cm (R16F's step at 32 m is 3 cm).
float probeSlack(float len) {
    return 0.03 * len + 0.02;
}

// The hit of ray p + t r (r unit) on what the probe captured (probes.distance_store): the ray is
// walked from the pixel to the proxy's t in params.z (probes.distance_steps) equal steps; the
// first step from clearly in front of the captured surface to behind it is refined by two secant
// steps (distance impostors: Szirmay-Kalos et al., "Approximate Ray-Tracing on the GPU with
// Distance Impostors", 2005). A refined point off the surface by more than probeSlack is the ray
// passing behind a silhouette as the capture point sees it, not a hit, and the walk goes on.
// Without a hit the proxy's t is kept: the walk never answers worse than the box where it finds
// nothing; it misses what is thinner than a step (README, failure modes). `hidden`: no hit, and
// the proxy's point lies behind what the capture point saw toward it (more than probeSlack), so
// the cube holds an occluder there, not what the ray meets.
float probeSurfaceT(Probe pr, vec3 p, vec3 r, float tProxy, out bool hidden) {
    vec3 o = p - pr.center.xyz;
    int steps = int(pr.params.z);
    // The first point clears the pixel's own surface, which the capture point may see.
    float tPrev = 0.02 * tProxy;
    float fPrev = probeBehind(pr, o + r * tPrev);
    float found = tProxy;
    bool done = false;
    for (int k = 1; k <= steps; ++k) {
        float t = tProxy * float(k) / float(steps);
        float f = probeBehind(pr, o + r * t);
        if (!done && fPrev < -probeSlack(length(o + r * tPrev)) && f >= 0.0) {
            float lo = tPrev, hi = t, flo = fPrev, fhi = f, ts = lo;
            for (int j = 0; j < 2; ++j) {
                // The secant on f clamped to the bracket's length: a point in front of the sky
                // is 65504 m in front, and the unclamped secant then lands on hi at once and
                // never nears the surface (failure_cases' overhead strip, 2026-12-07).
                float span = hi - lo, a = max(flo, -span), b = min(fhi, span);
                ts = lo + span * (-a) / max(b - a, 1e-6);
                float fs = probeBehind(pr, o + r * ts);
                if (fs < 0.0) {
                    lo = ts;
                    flo = fs;
                } else {
                    hi = ts;
                    fhi = fs;
                }
            }
            done = abs(flo) <= probeSlack(length(o + r * lo)) || abs(fhi) <= probeSlack(length(o + r * hi));
            found = done ? ts : found;
        }
        tPrev = t;
        fPrev = f;
    }
    // A hit on the proxy itself (a room's wall on its box) takes the proxy's exact t: the march's
    // is the distance cube's, a texel and a half-float step coarser, and moved the room's
    // reflected corners by a pixel (accuracy.registration, flat_screen_space).
    float slackAtProxy = probeSlack(length(o + r * tProxy));
    hidden = found == tProxy && fPrev > slackAtProxy;
    return abs(found - tProxy) <= slackAtProxy ? tProxy : found;
}
#endif

vec3 probeDirection(Probe pr, vec3 p, vec3 r) {
    return p + r * probeProxyT(pr, p, r) - pr.center.xyz;
}

// rgb: the probes' blended radiance (already weighted), a: the weight of what they captured
// (at most 1). A cube's alpha is its coverage by geometry (0 where the probe saw the sky, which
// is infinitely far and goes to the caller's sky along r instead), its rgb premultiplied by it;
// the caller gives 1 - a to the sky.
// `proxyDistance`: the influence-weighted distance along r to the probes' hits (the captured
// surface's or the proxy's; 0 where no probe reaches p), which the temporal pass reprojects the
// reflection by. `skyDir`: where the uncovered share's sky lies (r, or the reflected ray of the
// heaviest probe's captured mirror).
vec4 sampleProbes(uint count, vec3 p, vec3 n, vec3 r, float roughness, out float proxyDistance, out vec3 skyDir) {
    vec3 sum = vec3(0.0);
    float covered = 0.0;
    float total = 0.0;
    float distanceSum = 0.0;
    float skyWeight = 0.0;
    skyDir = r;
    for (uint i = 0u; i < count; ++i) {
        Probe pr = probes[i];
        float w = max(min(probeInfluence(pr, p, n), 1.0 - total), 0.0);
        float t = probeProxyT(pr, p, r);
        vec3 o = p, d = r;
        float F = 1.0;
        bool hidden = false;
#ifdef PROBES_DISTANCE_BINDING
        if (PROBES_NARROW_LOBES && roughness < kNarrowLobeMaxRoughness && pr.params.z > 0.0) {
            vec3 ru = normalize(r);
            t = probeSurfaceT(pr, p, ru, t, hidden);
            hidden = hidden && kProbeHiddenAlongRay && roughness < kProbeHiddenMaxRoughness;
            // A captured mirror where the ray lands (a smooth metal: the distance cube's gba is
            // its normal times its mean F0) holds its reflection toward the capture point, not
            // along this ray: the ray reflects there and reads the cube again, from the proxy.
            vec3 q = p + ru * t - pr.center.xyz;
            vec4 s = textureLod(probeDistance, vec4(q, pr.params.x), 0.0);
            float f0 = length(s.gba);
            vec3 mn = s.gba / max(f0, 1e-6);
            if (kProbeMirrorHits && f0 > 0.01 && abs(length(q) - s.r) <= probeSlack(length(q)) && dot(ru, mn) < 0.0) {
                o = p + ru * t;
                d = reflect(ru, mn);
                F = F_Schlick(vec3(f0), clamp(-dot(ru, mn), 0.0, 1.0)).x;
                t = probeProxyT(pr, o, d);
                if (w > skyWeight) skyDir = d;
            }
        }
#endif
        // A wide lobe's footprint on the proxy is t times its angle from here, but the cube's
        // mip blurs by the angle seen from the capture point: a lobe whose proxy point is nearer
        // to the pixel than to the capture point reads a sharper mip (Frostbite's distance-based
        // roughness, Lagarde and de Rousiers 2014: never rougher, and relaxed back toward the
        // roughness as it grows). Only from kNarrowLobeMaxRoughness up: below it the lobe is
        // narrow and its hit found on the captured surface, and there it cost plain_metals'
        // mirror band 0.19 dB (MEASUREMENTS.md in modules/reflections).
        vec3 look = hidden ? r : o + d * t - pr.center.xyz;
        float near = clamp(t / max(length(look), 1e-3) * roughness, 0.0, roughness);
        float lod = roughness < kNarrowLobeMaxRoughness ? roughness : mix(near, roughness, roughness);
        vec4 c = textureLod(probeCubes, vec4(look, pr.params.x), lod * pr.params.y);
        // A mirror's share of the sky (1 - a) goes along its reflected ray (skyDir), times F.
        sum += F * c.rgb * w;
        covered += (1.0 - F * (1.0 - c.a)) * w;
        total += w;
        distanceSum += t * w;
        skyWeight = max(skyWeight, w);
        if (total >= 0.999) break;
    }
    proxyDistance = total > 0.0 ? distanceSum / total : 0.0;
    return vec4(sum, covered);
}

vec4 sampleProbes(uint count, vec3 p, vec3 n, vec3 r, float roughness, out float proxyDistance) {
    vec3 unused;
    return sampleProbes(count, p, n, r, roughness, proxyDistance, unused);
}

vec4 sampleProbes(uint count, vec3 p, vec3 n, vec3 r, float roughness) {
    float unused;
    return sampleProbes(count, p, n, r, roughness, unused);
}

#endif
