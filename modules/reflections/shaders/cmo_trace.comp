#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.cmo_trace: the part of each reflected ray that screen space leaves uncovered (and,
// where it covers a pixel whole with a hit on a mirror, that hit's ray reflected again:
// mirror_hit.glsl), traced through the CMOs in their order (modules/probes/shaders/cmo.glsl:
// the hierarchical or the linear tracer), a hit shaded for the reflected ray's direction, and
// self-reflections: a hit on a mirror (shadeHit) reflects again, up to reflections.cmo_bounces,
// each ray with its own start where it leaves the surface (cmoLeaveSurface). The resolve takes
// the result as the chain's second link.
#include "common/brdf.glsl"
#include "engine/lighting_common.glsl"
#include "engine/scene_lights.glsl"
#include "reflections/shaders/common.glsl"
#include "reflections/shaders/material.glsl"
#include "reflections/shaders/relight.glsl"
#define CMO_RECORDS_BINDING 7
#define CMO_DISTANCE_BINDING 8
#define CMO_LAYERS_BINDING 9
#define CMO_ATTR_BINDING 10
#define CMO_ALBEDO_BINDING 11
#include "probes/shaders/cmo.glsl"
#define PLANAR_BUFFER_BINDING 16
#define PLANAR_IMAGES_BINDING 17
#include "probes/shaders/planar.glsl"
#include "reflections/shaders/chain.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;          // level 0: depth
layout(set = 0, binding = 2) uniform sampler2D normalTex;
layout(set = 0, binding = 3) uniform sampler2D emissiveTex;
layout(set = 0, binding = 5) uniform sampler2D hitTex;       // the screen-space trace's
layout(set = 0, binding = 6) uniform sampler2D guideTex;     // half: guidePixel()
layout(set = 0, binding = 13, rgba16f) uniform writeonly image2D cmoOut;
layout(set = 0, binding = 14, rgba16f) uniform writeonly image2D infoOut;
#include "reflections/shaders/mirror_hit.glsl"
#define CMO_RADIANCE_BINDING 12
#include "reflections/shaders/cmo_shade.glsl"  // shadeHit

// Ids above the scene lights' (0-287, scene_lights.glsl).
layout(constant_id = 300) const uint kHalf = 0u;    // reflections.resolution=half
layout(constant_id = 301) const uint kLinear = 0u;  // reflections.cmo_trace=linear
// Tile lists: the work list (tiles with a pixel in the CMO band that screen space leaves uncovered,
// listed by reflections.classify where no pixel traces a screen-space ray and by reflections.trace
// where one does) traces, the fill list writes "nothing found".
#include "reflections/shaders/tiles.glsl"

void main() {
    // With tiles, the tiles without CMO work keep reflections.cmo_clear's 0 in both outputs.
    ivec2 out_ = tilePixel(kListCmo);
    if (any(greaterThanEqual(out_, (ivec2(rf.size.xy) + int(kHalf)) >> kHalf))) return;
    ivec2 pixel = kHalf != 0u ? guidePixel(out_, texelFetch(guideTex, out_, 0)) : out_;
    vec4 result = vec4(0.0);
    vec4 info = vec4(0.0);
    float depth;
    vec4 normalRough;
    PixelMaterial m = readSurface(hiz, normalTex, emissiveTex, pixel, depth, normalRough);
    vec3 p = worldAt(vec2(pixel) + 0.5, depth);
    vec3 v = normalize(p - rfm.eye);
    vec3 n = normalize(normalRough.xyz);
    vec3 r = reflect(v, n);
    // The pixel's own ray where screen space leaves some of it (not for pixels a planar probe
    // serves: reflections.resolve takes its image there); else, where screen space covers it and
    // its hit is a mirror, that hit's ray reflected again (mirror_hit.glsl: resolve's mirrorHit
    // takes it, alpha -1, instead of the local probes' answer). reflections.trace listed this tile
    // only if some pixel of it passes one of these tests.
    vec4 hit = texelFetch(hitTex, out_, 0);
    bool covered = screenCovers(hit, p, r, v, m);  // false where nothing was traced (hit.z <= 0)
    MirrorHit h;
    bool first = inCmoBand(depth, m, planarServes(depth, m, p, n)) && !covered;
    bool second = !first && secondBounceInCmos(covered, vec2(pixel) + 0.5, hit, p, m.roughness, true, h);
    if (first || second) {
        int iterations = 0;
        float coneSlope = 2.0 * coneTan(second ? max(m.roughness, h.m.roughness) : m.roughness);
        vec3 origin = second ? h.position : p, normal = second ? h.n : n, dir = second ? reflect(h.d, h.n) : r;
        float travelled = second ? distance(p, h.position) : 0.0;
        float tHit;
        bool unresolved;
        int found = cmoFirstHit(origin, normal, dir, kLinear != 0u, iterations, tHit, unresolved);
        if (found < 0) {
            if (!second) info.z = unresolved ? 2.0 : 0.0;
        } else {
            CmoRecord c = cmos[found];
            vec3 hp = origin + dir * tHit;
            travelled += tHit;
            result.a = second ? -1.0 : max(tHit, 1e-3);
            info.y = second ? 0.0 : float(found + 1);
            info.z = second ? 0.0 : 1.0;
            bool mirror;
            vec3 hn, f0;
            vec3 shaded = shadeHit(c, hp, dir, coneSlope * travelled, mirror, hn, f0);
            // A hit whose captured normal faces along the ray is a surface seen from behind: the
            // texel the ray met belongs to another surface than the one it reached (a floor's
            // texel at the foot of a wall, where a ray leaving the floor meets the wall). Such a
            // hit is unresolved and goes down the chain (issue 24, "CMOs that never hurt": it
            // cost mirror_floor 0.36 dB along every seam against the room's exact box probe).
            if (dot(hn, dir) > 0.05) {
                result.a = 0.0;
                info.y = 0.0;
                info.z = second ? 0.0 : 2.0;
            } else if (mirror && int(rf.cmoBounces) > 0) {
                result.rgb = cmoSelfReflections(hp, hn, f0, dir, shaded, travelled, coneSlope, kLinear != 0u,
                                                iterations, info.w);
            } else {
                result.rgb = shaded;
            }
        }
        info.x = float(iterations);
        if (!finite3(result.rgb)) result = vec4(0.0);
    }
    imageStore(cmoOut, out_, result);
    imageStore(infoOut, out_, info);
}
