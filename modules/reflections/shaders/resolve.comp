#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.resolve: screen-space cone tracing (Uludag 4.4.5) from each pixel's hit, then the
// environment for what screen space does not cover. The cone of the reflection's roughness
// projects to an isosceles triangle from the pixel to the hit; circles inscribed in it, the
// largest at the hit end, are sampled from the pre-convolved colour pyramid at the mip of their
// size. Each sample weighs by the pre-integrated visibility there and by how far its sphere
// reaches behind the Hi-Z cell's closest surface, until the weights add up to one.
#include "common/brdf.glsl"
#include "engine/lighting_common.glsl"
#include "engine/scene_lights.glsl"
#include "reflections/shaders/common.glsl"
#include "reflections/shaders/material.glsl"
#include "reflections/shaders/stochastic.glsl"
#include "reflections/shaders/relight.glsl"
// Tile lists (reflections.classify; before the probes, whose march the rough variant compiles
// out): kListResolveCone runs all of it, kListResolveMirror all but the cone loop (every ray a
// mirror's), kListLookupNarrow (no pixel with a screen-space ray: its hits all read "not traced")
// compiles the screen-space term out, kListLookupRough also the steps that serve only lobes
// narrower than kNarrowLobeMaxRoughness (probe.h: the probes' distance march, the planar image,
// the grounds), and kListResolveFill writes what a pixel that reflects nothing gets. Each
// variant gives its pixels the full shader's values (capture.tiles_equal: the same bits but for
// a few values one half-float step apart, the rough variant's rounding of the same math).
#include "reflections/shaders/tiles.glsl"
const bool kNoRay = kTileMode == kTileModeLookup || kTileMode == kTileModeRough;
#define PROBES_NARROW_LOBES (kTileMode != kTileModeRough)
#define PROBES_BUFFER_BINDING 11
#define PROBES_CUBES_BINDING 12
#define PROBES_DISTANCE_BINDING 25
#include "probes/shaders/probes.glsl"
#define PLANAR_BUFFER_BINDING 16
#define PLANAR_IMAGES_BINDING 17
#define GROUND_BUFFER_BINDING 23
#define GROUND_IMAGES_BINDING 24
#include "probes/shaders/planar.glsl"
#include "probes/shaders/ground.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;          // texelFetch
layout(set = 0, binding = 2) uniform sampler2D normalTex;
layout(set = 0, binding = 3) uniform sampler2D emissiveTex;
layout(set = 0, binding = 5) uniform sampler2D hitTex;       // texelFetch
layout(set = 0, binding = 6) uniform sampler2D colorPyramid; // trilinear; alpha: pre-integrated visibility
layout(set = 0, binding = 8) uniform samplerCube envSpecular;
#include "reflections/shaders/chain.glsl"  // probesAndSky (after envSpecular)
layout(set = 0, binding = 9, rgba16f) uniform writeonly image2D reflectionOut;
layout(set = 0, binding = 10, rgba16f) uniform writeonly image2D methodOut;
layout(set = 0, binding = 7) uniform sampler2D guideTex;     // half: guidePixel()
layout(set = 0, binding = 13) uniform sampler2D cmoTex;      // reflections.cmo_trace: rgb, a first hit distance (0 none)
layout(set = 0, binding = 14, r32f) uniform writeonly image2D distanceOut;
layout(set = 0, binding = 19) uniform sampler2D litTex;     // this frame's lit image (mirrorHit)
layout(set = 0, binding = 20) uniform sampler2D albedoTex;  // rgb base colour, a metallic (mirrorHit)
layout(set = 0, binding = 21) uniform sampler2D dfgTex;     // linear clamp (mirrorHit)
layout(set = 0, binding = 22) uniform sampler2D shadowMaskTex;  // sun visibility (mirrorHit)
#include "reflections/shaders/mirror_hit.glsl"
// reflections.resolution (1: half): the full pixel the trace chose (the guide,
// reflections/guide.glsl), written at the invocation's half-resolution position.
layout(constant_id = 300) const uint kHalf = 0u;
// reflections.glossy (1: stochastic): glossy pixels resolve their own and four neighbours' GGX
// samples instead of a cone.
layout(constant_id = 301) const uint kStochastic = 0u;

// The reflected distance the temporal pass reprojects by (distanceOut): the screen-space hit's
// when screen space covers most, the CMO hit's or the probes' proxy distance when they do,
// kSkyDistance (common.glsl: a direction) when the sky does; 0: unknown (reproject by the
// surface); see main.

// The share of a glossy lobe that the cone leaves to the chain (the local probes' and the sky's
// lookups prefiltered at the pixel's roughness), however much of the cone screen space covers.
// The cone (brdf.glsl's Phong fit, cut where the lobe falls to 0.244, a half-angle of 1.19
// alpha) holds the GGX lobe's core, not its long tail: sampling GGX puts half its half vectors
// beyond atan(alpha) (tan^2 theta = alpha^2 xi / (1 - xi)), and 74% of its reflected directions
// outside the cone. Where they leave the surface screen space hit (a wall's top edge, with the
// sky above it, in a metal's glossy top) the cone gave the wall alone: plain_metals' roughness
// 0.2-0.3 pixels at 0.45 times the reference's level. The cone's mips blur past its edge, so the
// best share is below 74%. Mirror band against the 4-bounce references (error_sources.py) for
// shares 0 / 0.15 / 0.3 / 0.5 / 0.74: plain_metals 23.36 / 25.45 / 26.38 / 24.78 / 21.44 dB (its
// rough band 17.06 / 17.36 / 17.41 / 17.07 / 16.21), closed_room 23.10 / 23.11 / 23.09 / 22.96 /
// 22.65; the gallery's rough band 19.58 / 19.97 / 20.31 / 20.61 / 20.76 (MEASUREMENTS.md, issue
// 24, stop 62). Faded in from the mirror ray's roughness (kConeMinRoughness) to 0.1, so that the
// cutoff draws no seam. Only where the chain has a local probe, as mirrorHit's second bounce:
// without one the tail is the sky alone, which indoors is further off than the cone
// (closed_room.main without probes: mirror band 12.00 -> 9.26).
const float kConeTailShare = 0.3;
float coneTail(float roughness) {
    return rf.probeCount > 0u ? kConeTailShare * smoothstep(kConeMinRoughness, 0.1, roughness) : 0.0;
}

// Returns the cone's colour; `accumulated` is its summed visibility weight (at most 1).
vec3 coneTrace(vec2 start, float startDepth, vec3 hit, float roughness, out float accumulated) {
    vec2 delta = hit.xy - start;
    float len = length(delta);
    float tanTheta = coneTan(roughness);
    vec3 mirror = textureLod(colorPyramid, hit.xy * rf.size.zw, 0.0).rgb;
    accumulated = 1.0;
    if (tanTheta <= 0.0 || len < 1.0) return mirror;
    vec2 u = delta / len;
    float maxMip = float(textureQueryLevels(colorPyramid) - 1);
    int maxLevel = int(rf.hizLevels) - 1;
    float adjacent = len;
    vec3 sum = vec3(0.0);
    float total = 0.0;
    vec3 first = mirror;
    int samples = int(rf.coneSamples);
    for (int i = 0; i < samples; ++i) {
        float r = incircleRadius(2.0 * tanTheta * adjacent, adjacent);
        vec2 pos = start + u * (adjacent - r);
        float mip = clamp(log2(max(r, 1.0)), 0.0, maxMip);
        vec2 uv = pos * rf.size.zw;
        vec4 cv = textureLod(colorPyramid, uv, mip);
        vec3 c = cv.rgb;
        float vis = cv.a;
        // Depth is affine along the screen-space ray, so the sample's ray depth interpolates.
        float zRay = linearDepth(mix(startDepth, hit.z, (adjacent - r) / len));
        float radius = r * zRay * rf.pixelAngle;
        int level = clamp(int(round(mip)), 0, maxLevel);
        ivec2 cell = min(ivec2(pos) >> level, hizLevelSize(level) - 1);
        float zNear = linearDepth(texelFetch(hiz, cell, level).g);
        float sphere = radius > 0.0 ? clamp((zRay + radius - zNear) / (2.0 * radius), 0.0, 1.0) : 1.0;
        if (i == 0) first = c;
        float w = min(vis * sphere, 1.0 - total);
        sum += c * w;
        total += w;
        adjacent -= 2.0 * r;
        if (total >= 0.999 || adjacent < 1.0) break;
    }
    accumulated = total;
    return total > 1e-4 ? sum / total : first;
}

// A screen-space hit on a mirror (mirror_hit.glsl's findMirrorHit), shaded for the ray as the
// composite shades a pixel: its lit colour (this frame's, without environment specular) plus its
// reflection along the ray reflected again, times its F0 A + B, with the lights' highlights moved
// from the camera's view to the ray's (relight.glsl, as the CMO trace does). That second bounce is
// what reflections.cmo_trace found for it (`second`, alpha -1: a CMO hit) or else the local probes
// and the sky. The converged reference traces it; on cornell_mirrors.main the pyramid's value was
// 72% of the mirror band's squared error on 12% of its pixels (9.8 dB there; MEASUREMENTS.md,
// issue 24). Returns false where the hit is no such mirror (the pyramid's value stays);
// `behind`: it is such a mirror seen from behind (its sub-pixel normal faces away from the ray:
// the ray passed behind its silhouette, a floor's ray under a sphere meeting its unseen underside).
bool mirrorHit(vec3 hit, vec3 p, vec4 second, out vec3 radiance, out bool behind) {
    radiance = vec3(0.0);
    MirrorHit h;
    bool found = findMirrorHit(hit, p, true, h);
    // findMirrorHit sets the ray's direction only once the material qualifies.
    behind = !found && dot(h.d, h.d) > 0.0 && dot(h.n, -h.d) <= 0.0;
    if (!found) return false;
    vec4 probe;
    float proxyDistance;
    vec3 again = second.a < 0.0 ? second.rgb
                                : probesAndSky(h.position, h.n, reflect(h.d, h.n), h.m.roughness, probe, proxyDistance);
    vec4 albedo = texelFetch(albedoTex, h.q, 0);
    vec2 dfg = textureLod(dfgTex, vec2(dot(h.n, -h.d), h.m.roughness), 0.0).rg;
    float sun = kDirectionalLights > 0u ? texelFetch(shadowMaskTex, h.q, 0).r : 1.0;
    vec3 moved = movedDirect(h.position, h.n, -h.d, normalize(rfm.eye - h.position), albedo.rgb, albedo.a,
                             h.normalRough.w, sun);
    radiance = max(texelFetch(litTex, h.q, 0).rgb + moved, vec3(0.0)) +
               again * (specularF0(albedo.rgb, albedo.a) * dfg.x + dfg.y);
    return finite3(radiance);
}

// Stochastic glossy: the screen-space radiance of this pixel's lobe from its own ray and its four
// neighbours' (Stachowiak 2015's ray reuse). Each hit is weighed by this pixel's BRDF times
// cosine toward it over the pdf with which the neighbour drew its ray (recomputed from the
// neighbour's noise, reflections/stochastic.glsl), a ratio estimator whose weights also count the
// rays that missed: `coverage` is the hits' share of the weight, as a cone's visibility is.
// Neighbours on another surface (normal off by 25 degrees, roughness by 0.1) are not reused. A
// hit on a mirror is shaded for its ray (mirrorHit), each ray being a sharp one.
vec3 stochasticResolve(ivec2 out_, vec3 p, vec3 v, vec3 n, float roughness, out float coverage,
                       out float hitDistance) {
    const ivec2 kReuse[5] = ivec2[](ivec2(0, 0), ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
    ivec2 traceSize = (ivec2(rf.size.xy) + int(kHalf)) >> kHalf;
    float alpha = roughnessToAlpha(roughness);
    float NoV = max(dot(n, -v), 1e-4);
    vec3 sum = vec3(0.0);
    float wHit = 0.0, wAll = 0.0, distSum = 0.0;
    for (int k = 0; k < 5; ++k) {
        ivec2 s = clamp(out_ + kReuse[k], ivec2(0), traceSize - 1);
        ivec2 q = kHalf != 0u ? guidePixel(s, texelFetch(guideTex, s, 0)) : s;
        float qDepth = texelFetch(hiz, q, 0).g;
        vec4 qNormalRough = texelFetch(normalTex, q, 0);
        PixelMaterial qm = pixelMaterial(texelFetch(emissiveTex, q, 0).a, qNormalRough.w);
        vec3 qn = normalize(qNormalRough.xyz);
        if (!(qDepth > 0.0 && qm.reflective) || dot(qn, n) < 0.9 || abs(qm.roughness - roughness) > 0.1) continue;
        vec3 qv = normalize(worldAt(vec2(q) + 0.5, qDepth) - rfm.eye);
        vec3 ql = stochasticDirection(q, qv, qn, qm.roughness);
        float qpdf = visibleNormalPdf(qn, -qv, ql, roughnessToAlpha(qm.roughness));
        vec4 hit = texelFetch(hitTex, s, 0);
        bool isHit = hit.z > 0.0;
        vec3 hp = isHit ? worldAt(hit.xy, hit.z) : p;
        vec3 l = isHit ? normalize(hp - p) : ql;
        float NoL = dot(n, l);
        if (NoL <= 0.0 || !finite3(l)) continue;
        vec3 h = normalize(l - v);
        float w = D_GGX(max(dot(n, h), 0.0), alpha) * V_SmithGGXCorrelated(NoV, NoL, alpha) * NoL / max(qpdf, 1e-6);
        wAll += w;
        if (isHit) {
            float d = distance(hp, p);
            float wf = w * edgeFade(hit.xy) * distanceFade(d) * cameraFade(dot(l, v));
            vec3 c;
            bool unused;
            if (!mirrorHit(hit.xyz, p, vec4(0.0), c, unused)) c = textureLod(colorPyramid, hit.xy * rf.size.zw, 0.0).rgb;
            sum += wf * c;
            wHit += wf;
            distSum += wf * d;
        }
    }
    coverage = wAll > 0.0 ? wHit / wAll : 0.0;
    hitDistance = wHit > 0.0 ? distSum / wHit : 0.0;
    return wHit > 0.0 ? sum / wHit : vec3(0.0);
}

void main() {
    ivec2 out_ = tilePixel(kTileMode == kTileModeFill     ? kListResolveFill
                           : kTileMode == kTileModeLookup ? kListLookupNarrow
                           : kTileMode == kTileModeRough  ? kListLookupRough
                           : kTileMode == kTileModeMirror ? kListResolveMirror
                                                          : kListResolveCone);
    if (any(greaterThanEqual(out_, (ivec2(rf.size.xy) + int(kHalf)) >> kHalf))) return;
    if (kTileMode == kTileModeFill) {
        imageStore(reflectionOut, out_, vec4(0.0));
        imageStore(methodOut, out_, vec4(0.0));
        imageStore(distanceOut, out_, vec4(0.0));
        return;
    }
    ivec2 pixel = kHalf != 0u ? guidePixel(out_, texelFetch(guideTex, out_, 0)) : out_;
    vec4 reflection = vec4(0.0);
    vec4 method = vec4(0.0);
    float distance_ = 0.0;
    float depth;
    vec4 normalRough;
    PixelMaterial m = readSurface(hiz, normalTex, emissiveTex, pixel, depth, normalRough);
    if (depth > 0.0 && m.reflective) {
        vec2 px = vec2(pixel) + 0.5;
        vec3 p = worldAt(px, depth);
        vec3 v = normalize(p - rfm.eye);
        vec3 n = normalize(normalRough.xyz);
        vec3 r = reflect(v, n);
        vec3 screen = vec3(0.0);
        float coverage = 0.0;
        vec4 hit = kNoRay ? vec4(-1.0) : texelFetch(hitTex, out_, 0);
        float hitDistance = 0.0;
        // On a planar probe's plane the mirrored view is exact and takes the pixel (no screen-space
        // term) up to planarShare's roughness, fading to the rest of the chain above it (its box
        // mips stand in for a GGX lobe only when the lobe is narrow). Screen space's false hits
        // behind thin objects (a sphere's unseen underside reflected in the floor under it) were
        // streaks of the wrong colour there; keeping only the screen-space hits that agreed with
        // the planar image on distance and position scored 32.9 / 34.4 dB against 33.2 / 33.6
        // planar alone on mirror_floor, and its choice flipping from pixel to pixel drew moire
        // along the gallery's reflected edges (modules/reflections/MEASUREMENTS.md, "planar probes").
        int planar = PROBES_NARROW_LOBES && rf.planarCount > 0u ? planarAt(rf.planarCount, p, n, rfm.eye) : -1;
        float planarWeight = planar >= 0 ? planarShare(m.roughness) : 0.0;
        if (planarWeight >= 1.0 || kNoRay) {
        } else if (kStochastic != 0u && kTileMode != kTileModeMirror && m.roughness >= kStochasticMinRoughness) {
            if (m.screenSpace && m.roughness <= m.maxScreenSpace) {
                screen = stochasticResolve(out_, p, v, n, m.roughness, coverage, hitDistance);
                coverage *= clamp((m.maxScreenSpace - m.roughness) / 0.1, 0.0, 1.0);
            }
        } else if (hit.z > 0.0) {
            hitDistance = distance(worldAt(hit.xy, hit.z), p);
            // A mirror tile's rays have no cone (coneTrace's own first answer).
            float accumulated = 1.0;
            screen = kTileMode == kTileModeMirror ? textureLod(colorPyramid, hit.xy * rf.size.zw, 0.0).rgb
                                                  : coneTrace(px, depth, hit.xyz, m.roughness, accumulated);
            // A mirror hit replaces the cone's colour where the cone is narrow at the hit.
            float share = mirrorHitShare(px, hit.xy, m.roughness);
            vec3 again;
            bool behind = false;
            if (share > 0.0 && mirrorHit(hit.xyz, p, rf.cmoCount > 0u ? texelFetch(cmoTex, out_, 0) : vec4(0.0), again, behind))
                screen = mix(screen, again, share);
            float fades = edgeFade(hit.xy) * cameraFade(dot(r, v)) *
                          distanceFade(hitDistance) *
                          clamp((m.maxScreenSpace - m.roughness) / 0.1, 0.0, 1.0);
            coverage = clamp((rf.coverageMode == 0u ? 1.0 : accumulated) * fades, 0.0, 1.0) *
                       (1.0 - coneTail(m.roughness));
            // Without multi-bounce the pyramid holds the mirror's bare lit colour, black for a
            // metal: such a hit drew a black sawtooth under the game's chrome sphere. Down the
            // chain instead (+0.02 dB for low without multi-bounce). With multi-bounce the
            // pyramid's last-frame reflection there scored closer than the chain (the default's
            // mirror band 21.68 against 21.63 dB with the rule; MEASUREMENTS.md, 2026-12-06).
            if (behind && rf.multiBounce == 0u) coverage = 0.0;
        }
        // Where the planar probe takes only a share (a glossy band), screen space keeps its hit
        // only if the planar image agrees on the mirror ray's distance (5% and 5 cm): a false
        // hit behind a thin object there drew sawtooth streaks beside the gallery torus's
        // reflection in its 0.3 floor band; rejected, the pixel goes down the chain instead.
        if (planar >= 0 && planarWeight < 1.0 && coverage > 0.0) {
            float d = planarDistance(planar, p);
            if (!(abs(hitDistance - d) <= 0.05 * d + 0.05)) coverage = 0.0;
        }
        // The fallback chain beyond screen space: the CMOs (what reflections.cmo_trace found),
        // then local probes, then the sky, only where screen space leaves something (the probe
        // lookup is most of this pass's cost past the cone); the planar probe's share over it all.
        vec4 probe = vec4(0.0);
        vec3 env = vec3(0.0);
        float proxyDistance = 0.0;
        float cmoWeight = 0.0;
        vec4 cmo = vec4(0.0);
        if ((coverage < 1.0 || !finite3(screen)) && planarWeight < 1.0) {
            if (rf.cmoCount > 0u) cmo = texelFetch(cmoTex, out_, 0);
            cmoWeight = cmo.a > 0.0 ? 1.0 : 0.0;
            if (cmoWeight < 1.0) {
                env = probesAndSky(p, n, r, m.roughness, probe, proxyDistance);
            } else {
                env = cmo.rgb;
            }
        }
        vec3 radiance = mix(env, screen, coverage);
        if (!finite3(radiance)) radiance = env;
        float planarDistance = 0.0;
        if (planarWeight > 0.0) {
            vec4 pl = samplePlanar(planar, p, r, m.roughness, distance(p, rfm.eye));
            radiance = mix(radiance, pl.rgb, planarWeight);
            planarDistance = pl.a;
        }
        reflection = vec4(max(radiance, vec3(0.0)), coverage * (1.0 - planarWeight));
        // A planar probe's share counts with the probes' (g): the method AOV has four channels.
        float rest = (1.0 - coverage) * (1.0 - cmoWeight);
        method = vec4(coverage, rest * probe.a, rest * (1.0 - probe.a), (1.0 - coverage) * cmoWeight) *
                     (1.0 - planarWeight) + vec4(0.0, planarWeight, 0.0, 0.0);
        float top = max(max(method.r, method.g), max(method.b, method.a));
        distance_ = planarWeight >= 0.5 ? planarDistance
                    : method.r >= top   ? hitDistance
                    : method.a >= top   ? cmo.a
                    : method.b >= top   ? kSkyDistance
                                        : proxyDistance;
    }
    imageStore(reflectionOut, out_, reflection);
    imageStore(methodOut, out_, method);
    imageStore(distanceOut, out_, vec4(distance_));
}
