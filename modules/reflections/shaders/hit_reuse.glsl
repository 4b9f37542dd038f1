// reflections.hit_reuse: at half resolution, a mirror pixel that its 2x2 did not trace finds its
// own hit from its neighbours' hits, over what reflections.upsample wrote. hit_reuse.comp is the
// screen-space half alone, hit_reuse_cmo.comp (HIT_REUSE_CMOS, reflections.hit_reuse_cmo on the
// CMO tiles after it) adds the CMOs' hits.
//
// Why: a mirror's reflection holds the reflected scene's full detail, and upsampling it from half
// size blurs every reflected edge by a pixel or two: most of what half resolution loses in the
// mirror band (MEASUREMENTS.md, issue 23, "hit reuse").
//
// How (Stachowiak 2015 reuses a neighbour's hit for a pixel's own lobe; here for its own mirror
// ray): each of the four half-size samples around the pixel (the bilinear ones the upsampling
// weighs) whose chain one link took whole gives a hit and the surface there. The pixel's own
// ray p + t r is stepped onto that surface's tangent plane, t = dot(S - p, nS) / dot(r, nS), and
// once more from the surface found at the new point (a curved hit surface). A candidate is kept
// where the surface there lies within 2% of the point's own distance; the closest agreement wins.
//   - Screen space (a sample that screen space covered whole): the surface is the depth buffer's
//     and its G-buffer normal; the colour is read where resolve reads a mirror ray's, the colour
//     pyramid's level 0, bilinearly, at the sub-pixel hit.
//   - CMOs (a sample a CMO took whole): the surface is the CMO's captured distance (bilinear
//     where smooth, cmo.glsl) and its captured normal; the hit is shaded as reflections.cmo_trace
//     shades it, a mirror's self-reflections traced on from there (cmo_shade.glsl).
// Screen space first, as the chain: the CMOs' candidates count only where no screen-space one
// agrees.
//
// Left as the upsampling wrote them: the traced pixel of each 2x2 (its own value already),
// pixels rougher than a mirror ray (kConeMinRoughness: a cone reads blurred mips, which upsample
// well), screen-space hits on mirrors (resolve shades those for the ray, mirror_hit.glsl), hits the fades would weaken (the screen's edges, the distance fade,
// rays toward the camera), and pixels with no candidate that agrees (the ray passes where no
// neighbour's hit surface is: a silhouette).
#include "reflections/shaders/common.glsl"
#include "reflections/shaders/material.glsl"
#ifdef HIT_REUSE_CMOS
#include "common/brdf.glsl"
#include "engine/lighting_common.glsl"
#include "engine/scene_lights.glsl"
#include "reflections/shaders/relight.glsl"
#define CMO_RECORDS_BINDING 11
#define CMO_DISTANCE_BINDING 12
#define CMO_LAYERS_BINDING 13
#define CMO_ATTR_BINDING 14
#define CMO_ALBEDO_BINDING 16
#include "probes/shaders/cmo.glsl"
#define CMO_RADIANCE_BINDING 17
#include "reflections/shaders/cmo_shade.glsl"  // shadeHit
layout(set = 0, binding = 19) uniform sampler2D cmoTex;      // half: rgb, a first hit distance
layout(set = 0, binding = 20) uniform sampler2D cmoInfoTex;  // half: y the CMO (1-based)
layout(constant_id = 301) const uint kLinear = 0u;  // reflections.cmo_trace=linear (a mirror hit's next ray)
#endif

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;          // level 0 .g: depth (texelFetch)
layout(set = 0, binding = 2) uniform sampler2D normalTex;
layout(set = 0, binding = 3) uniform sampler2D emissiveTex;
layout(set = 0, binding = 5) uniform sampler2D hitTex;       // half: the trace's hits
layout(set = 0, binding = 6) uniform sampler2D colorPyramid; // trilinear
layout(set = 0, binding = 7) uniform sampler2D guideTex;     // half: guidePixel()
layout(set = 0, binding = 10) uniform sampler2D methodTex;   // half: the resolve's method weights
layout(set = 0, binding = 8) uniform sampler2D halfTex;      // half: the resolve's reflection
layout(set = 0, binding = 21) uniform samplerCube envSpecular;  // the prefiltered sky
layout(set = 0, binding = 9, rgba16f) uniform writeonly image2D reflectionOut;  // full: the upsampled reflection
#include "reflections/shaders/mirror_hit.glsl"
// The footprints of the reflective tiles (tiles.glsl, as lookup_full takes them). Ids past the
// scene lights' (0-287).
#include "reflections/shaders/tiles.glsl"
layout(constant_id = 302) const uint kTileScale = 2u;
layout(constant_id = 303) const uint kList = 0u;
// The lookup tiles' variant has no screen-space term: none of their samples traced a ray.
const bool kScreenCandidates = kTileMode == kTileModeScreen || kList != kListLookup;

// How far the surface may lie from a candidate point: 2% of its distance, the upsampling's own
// plane tolerance.
const float kAgreement = 0.02;
// Four samples whose luminances lie within this share of the largest are smooth there.
const float kSmooth = 0.05;

bool onScreen(vec3 x) {
    return all(greaterThanEqual(x.xy, vec2(0.0))) && all(lessThan(x.xy, rf.size.xy)) && x.z > 0.0;
}

// Where the ray p + t r meets the plane through s with normal ns: t, or -1 where the plane faces
// away from the ray.
float planeT(vec3 p, vec3 r, vec3 s, vec3 ns) {
    float denom = dot(r, ns);
    return denom < -1e-3 ? dot(s - p, ns) / denom : -1.0;
}

// The pixel's ray stepped onto the tangent plane of the depth buffer's surface at screen point
// `at` (pixels): the new t, or -1.
float planeStep(vec3 p, vec3 r, ivec2 at) {
    float z = texelFetch(hiz, at, 0).g;
    return z > 0.0 ? planeT(p, r, worldAt(vec2(at) + 0.5, z), normalize(texelFetch(normalTex, at, 0).xyz)) : -1.0;
}

// The best screen-space candidate: xy the sub-pixel hit, z its depth (0: none agrees).
vec3 screenCandidate(ivec2 base, ivec2 lowSize, vec3 p, vec3 r) {
    float nearest = 1e30;
    vec3 bestHit = vec3(0.0);
    for (int i = 0; i < 4; ++i) {
        ivec2 s = clamp(base + ivec2(i & 1, i >> 1), ivec2(0), lowSize - 1);
        vec4 hit = texelFetch(hitTex, s, 0);
        bool usable = hit.z > 0.0 && texelFetch(methodTex, s, 0).r >= 0.999;
        float t = usable ? planeStep(p, r, clamp(ivec2(hit.xy), ivec2(0), ivec2(rf.size.xy) - 1)) : -1.0;
        vec3 x = projectToScreen(p + r * max(t, 0.0));
        t = t > 0.0 && onScreen(x) ? planeStep(p, r, ivec2(x.xy)) : -1.0;
        x = projectToScreen(p + r * max(t, 0.0));
        bool inside = t > 0.0 && onScreen(x);
        float z = inside ? texelFetch(hiz, ivec2(x.xy), 0).g : 0.0;
        float zx = linearDepth(max(x.z, 1e-9));
        float off = z > 0.0 ? abs(linearDepth(z) - zx) / zx : 1.0;
        bool better = inside && off < kAgreement && t < nearest && edgeFade(x.xy) >= 1.0 && distanceFade(t) >= 1.0;
        nearest = better ? t : nearest;
        bestHit = better ? vec3(x.xy, z) : bestHit;
    }
    return bestHit;
}

#ifdef HIT_REUSE_CMOS
// The CMO's captured surface toward u (from its centre): its distance, bilinear where smooth, and
// its normal. Returns false at the edge of an opening (cmoSmooth's skyEdge) or toward the sky.
bool cmoSurface(CmoRecord c, vec3 u, out float d, out vec3 ns) {
    int f = cmoFace(u);
    vec3 m, s, t;
    cmoAxes(f, m, s, t);
    bool skyEdge;
    d = cmoDistanceSmooth(c, f, m, s, t, u, skyEdge);
    ivec3 texel = cmoTexel(c, u);
    ns = normalize(texelFetch(cmoAttr, ivec3(texel.xy, int(c.params.x) + texel.z), int(c.params.y)).xyz);
    return !skyEdge && d < kCmoSky;
}

// The best CMO candidate: x the CMO's index, y the ray's t (< 0: none agrees). A candidate's
// point is the ray's on the tangent plane of the captured surface toward the neighbour's hit;
// it is kept where the captured surface toward that point agrees, and then stepped once more onto
// the tangent plane found there (no third look-up: each costs five fetches, and lavapipe pays
// every candidate's for every pixel).
vec2 cmoCandidate(ivec2 base, ivec2 lowSize, vec3 p, vec3 r) {
    float nearest = 1e30;
    vec2 bestHit = vec2(-1.0);
    for (int i = 0; i < 4; ++i) {
        ivec2 s = clamp(base + ivec2(i & 1, i >> 1), ivec2(0), lowSize - 1);
        vec4 info = texelFetch(cmoInfoTex, s, 0);
        float tHit = texelFetch(cmoTex, s, 0).a;
        bool usable = texelFetch(methodTex, s, 0).a >= 0.999 && tHit > 0.0 && info.y >= 1.0;
        int k = clamp(int(info.y) - 1, 0, int(rf.cmoCount) - 1);
        CmoRecord c = cmos[k];
        // Onto the plane at the neighbour's hit.
        vec3 u = p + r * tHit - c.center.xyz;
        float d;
        vec3 ns;
        bool ok = usable && cmoSurface(c, u, d, ns);
        float t = ok ? planeT(p, r, c.center.xyz + normalize(u) * d, ns) : -1.0;
        // The surface there, and the plane once more.
        u = p + r * max(t, 0.0) - c.center.xyz;
        ok = t > 0.0 && cmoSurface(c, u, d, ns);
        float off = ok ? abs(length(u) - d) / max(d, 1e-6) : 1.0;
        t = ok ? planeT(p, r, c.center.xyz + normalize(u) * d, ns) : -1.0;
        bool better = off < kAgreement && t > 0.0 && t < nearest;
        nearest = better ? t : nearest;
        bestHit = better ? vec2(float(k), t) : bestHit;
    }
    return bestHit;
}
#endif

void reusePixel(ivec2 pixel) {
    ivec2 lowSize = (ivec2(rf.size.xy) + 1) >> 1;
    ivec2 own = pixel >> 1;
    if (guidePixel(own, texelFetch(guideTex, own, 0)) == pixel) return;  // traced: its own value
    float depth;
    vec4 normalRough;
    PixelMaterial m = readSurface(hiz, normalTex, emissiveTex, pixel, depth, normalRough);
    if (!(depth > 0.0 && m.reflective && m.roughness < kConeMinRoughness)) return;
    vec3 p = worldAt(vec2(pixel) + 0.5, depth);
    vec3 v = normalize(p - rfm.eye);
    vec3 r = reflect(v, normalize(normalRough.xyz));
    ivec2 base = ivec2(floor((vec2(pixel) + 0.5) * 0.5 - 0.5));
    // What answered the four samples, and how far apart their values lie. Where they agree, the
    // upsampling is already what the pixel's own ray gives; where no link took a sample whole
    // (a planar probe's floor, the local probes' rough walls) there is no hit to reuse. Either
    // way the pixel leaves here, and on lavapipe a row of eight that all leave skips the rest.
    float lo = 1e30, hi = 0.0, sky = 1.0;
    bool ownScreen = false, ownCmo = false;
    for (int i = 0; i < 4; ++i) {
        ivec2 s = clamp(base + ivec2(i & 1, i >> 1), ivec2(0), lowSize - 1);
        float y = dot(texelFetch(halfTex, s, 0).rgb, vec3(0.2126, 0.7152, 0.0722));
        vec4 method = texelFetch(methodTex, s, 0);
        lo = min(lo, y);
        hi = max(hi, y);
        sky = min(sky, method.b);
        // A screen-space or CMO hit only where a sample in the pixel's own tile took one: the
        // tiled passes run on the lists its tile is on (a ray's, the CMOs'), and this keeps them
        // equal to the whole screen's.
        bool sameTile = all(equal(s / int(kTileSize), own / int(kTileSize)));
        ownScreen = ownScreen || (sameTile && method.r >= 0.999);
        ownCmo = ownCmo || (sameTile && method.a >= 0.999);
    }
    if (hi - lo <= kSmooth * hi + 1e-4 || !(ownScreen || ownCmo || sky >= 0.999)) return;
    // Where the sky alone answered all four samples, it answers the pixel's own ray (one look-up:
    // a curved mirror's sky changes from pixel to pixel; cornell_mirrors.main's sphere and torus).
    if (sky >= 0.999) {
        vec3 c = textureLod(envSpecular, r, m.roughness * rf.envMaxMip).rgb;
        if (finite3(c)) imageStore(reflectionOut, pixel, vec4(max(c, vec3(0.0)), 0.0));
        return;
    }
    // Screen space takes the pixel whole only where resolve's fades are all 1 (chain.glsl's
    // screenCovers): the roughness fade is 1 up to maxScreenSpace - 0.1.
    bool screen = kScreenCandidates && ownScreen && m.screenSpace && m.roughness <= m.maxScreenSpace - 0.1 && rf.coverageMode == 0u &&
                  cameraFade(dot(r, v)) >= 1.0;
    vec3 hit = screen ? screenCandidate(base, lowSize, p, r) : vec3(0.0);
    if (hit.z > 0.0) {
        MirrorHit h;
        if (findMirrorHit(hit, p, false, h)) return;  // resolve shades a mirror hit for its ray
        vec3 c = textureLod(colorPyramid, hit.xy * rf.size.zw, 0.0).rgb;
        if (finite3(c)) imageStore(reflectionOut, pixel, vec4(max(c, vec3(0.0)), 1.0));
        return;
    }
#ifdef HIT_REUSE_CMOS
    if (!(ownCmo && m.traceCmos && m.roughness <= rf.cmoMaxRoughness)) return;
    vec2 cmo = cmoCandidate(base, lowSize, p, r);
    if (cmo.y <= 0.0) return;
    bool mirror;
    vec3 n, f0;
    vec3 c = shadeHit(cmos[int(cmo.x)], p + r * cmo.y, r, 0.0, mirror, n, f0);
    if (!mirror && finite3(c)) imageStore(reflectionOut, pixel, vec4(c, 0.0));
#endif
}

void main() {
    ivec2 pixel = kTileMode == kTileModeScreen ? ivec2(gl_GlobalInvocationID.xy) : footprintBlockPixel(kList, kTileScale);
    if (all(lessThan(pixel, ivec2(rf.size.xy)))) reusePixel(pixel);
}
