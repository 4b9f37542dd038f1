#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
// reflections.classify: what each 8x8 tile of the trace's resolution needs (tiles.h), as tile
// lists the per-pixel passes dispatch from. A pixel needs
//   - a screen-space ray: reflective, screen-space mode, no rougher than its screen-space limit,
//     not taken whole by a planar probe (exactly the trace's own test but the camera fade, whose
//     ray direction is stochastic in one mode: a tile is never left out that would trace);
//   - the CMOs: reflective, CMOs in its chain, no rougher than cmo_max_roughness, not planar, and
//     not covered by screen space (the trace lists the tiles with a ray, when it knows that);
//   - a resolve: reflective at all (else its reflection is 0);
//   - a cone: a ray whose cone may be wider than the mirror's (kConeMinRoughness): a tile of
//     mirror rays alone is resolved without the cone loop;
//   - a narrow lobe: reflective, smoother than kNarrowLobeMaxRoughness (probe.h): a tile of
//     wider lobes alone is resolved without the probes' distance march, the planar
//     probes and their grounds, which serve only narrower ones.
// Above the screen-space limit a reflective tile is a lookup (probes and sky, no ray). At half
// resolution this pass also chooses the pixel each half pixel traces and writes the guide
// (reflections/guide.glsl), which the trace used to: the choice is needed to classify.
#include "reflections/shaders/common.glsl"
#include "reflections/shaders/material.glsl"
#define PLANAR_BUFFER_BINDING 16
#define PLANAR_IMAGES_BINDING 17
#include "probes/shaders/planar.glsl"
#include "reflections/shaders/chain.glsl"
#define SPECULUM_TILES_WRITE
#include "reflections/shaders/tiles.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D hiz;         // level 0: depth
layout(set = 0, binding = 2) uniform sampler2D normalTex;   // xyz normal, w roughness
layout(set = 0, binding = 3) uniform sampler2D emissiveTex; // a: flags | material index
layout(set = 0, binding = 6, rgba32f) uniform writeonly image2D guideOut;  // half only
layout(constant_id = 1) const uint kHalf = 0u;
// reflections.ray_budget=quarter: the half pixel's choice rotates over its 2x2 frame by frame.
layout(constant_id = 2) const uint kQuarter = 0u;
// The rotation's start per frame, a 2x2 Bayer order (0, 3, 1, 2: diagonal pixels apart), offset
// per half pixel so that neighbouring blocks refresh different corners in the same frame.
int rotationStart(ivec2 halfPixel) {
    const int kOrder[4] = int[](0, 3, 1, 2);
    return kOrder[(int(rf.frameIndex) + (halfPixel.x & 1) + 2 * (halfPixel.y & 1)) & 3];
}
#define SPECULUM_REFLECTIONS_GUIDE_CHOOSE
#include "reflections/shaders/guide.glsl"

void append(uint list, uint tile) {
    uint i = atomicAdd(tiles.args[list].x, 1u);
    tiles.entries[i * kTileLists + list] = tile;
}

void main() {
    ivec2 out_ = ivec2(gl_GlobalInvocationID.xy);
    uint mine = 0u;
    if (all(lessThan(out_, (ivec2(rf.size.xy) + int(kHalf)) >> kHalf))) {
        ivec2 pixel = out_;
        float depth;
        vec4 normalRough;
        float flags;
        if (kHalf != 0u) {
            GuideChoice c = chooseGuidePixel(out_, kQuarter != 0u ? rotationStart(out_) : -1);
            pixel = c.pixel;
            depth = c.depth;
            normalRough = c.normalRough;
            flags = c.flags;
            vec3 world = depth > 0.0 ? worldAt(vec2(pixel) + 0.5, depth) : vec3(0.0);
            imageStore(guideOut, out_, vec4(world, packGuide(c.index, c.reflective, normalRough.w, normalRough.xyz)));
        } else {
            depth = texelFetch(hiz, pixel, 0).g;
            normalRough = texelFetch(normalTex, pixel, 0);
            flags = texelFetch(emissiveTex, pixel, 0).a;
        }
        PixelMaterial m = pixelMaterial(flags, normalRough.w);
        if (depth > 0.0 && m.reflective) {
            vec3 p = worldAt(vec2(pixel) + 0.5, depth);
            bool planar = planarServes(depth, m, p, normalize(normalRough.xyz));
            mine = kNeedResolve | (m.roughness < kNarrowLobeMaxRoughness ? kNeedNarrow : 0u);
            if (m.screenSpace && m.roughness <= m.maxScreenSpace && !planar)
                mine |= kNeedRay | (m.roughness >= kConeMinRoughness ? kNeedCone : 0u);
            if (inCmoBand(depth, m, planar)) mine |= kNeedCmo;
        }
    }
    // The tile's needs without a workgroup barrier (two of them cost this pass 4-7 of its 17 ms
    // on lavapipe at 960x540): each subgroup ORs its lanes' needs, and its first lane adds them
    // into the tile's word (tiles.h, kListArrivals) in bits of its own, 3 per subgroup, with its
    // arrival counted in bits 24-27; the subgroup that arrives last has every bit and appends the
    // tile. The resolve's two rarer needs (a cone, a narrow lobe) are ORed into bits 28 and 29
    // first, by the subgroups that have them only (one atomic per subgroup on most tiles): a
    // location's atomics are ordered as each invocation issues them, so the last add returns
    // them too. Needs at most 8 subgroups per 64 invocations (a subgroup size of 8 or more:
    // every desktop GPU and lavapipe).
    uint sub = subgroupOr(mine);
    if (subgroupElect()) {
        uint word = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * kTileLists + kListArrivals;
        uint rare = sub & (kNeedCone | kNeedNarrow);
        if (rare != 0u) atomicOr(tiles.entries[word], rare << kArrivalRareShift);
        uint add = ((sub & 7u) << (3u * gl_SubgroupID)) + (1u << kArrivalCountShift);
        uint before = atomicAdd(tiles.entries[word], add);
        if (((before >> kArrivalCountShift) & 15u) == gl_NumSubgroups - 1u) {
            uint n = tileNeeds(before + add);
            uint tile = gl_WorkGroupID.x | (gl_WorkGroupID.y << 16);
            bool ray = (n & kNeedRay) != 0u;
            if (ray) append(kListTrace, tile);
            // A tile with a ray gets its CMO list from reflections.trace, which knows what screen
            // space covers; without one, nothing is covered.
            if (!ray && (n & kNeedCmo) != 0u) append(kListCmo, tile);
            // The resolve's lists, and the two the other full-size passes take whole.
            if (ray) {
                append(kListResolveRay, tile);
                append((n & kNeedCone) != 0u ? kListResolveCone : kListResolveMirror, tile);
            } else if ((n & kNeedResolve) != 0u) {
                append(kListLookup, tile);
                append((n & kNeedNarrow) != 0u ? kListLookupNarrow : kListLookupRough, tile);
            } else {
                append(kListResolveFill, tile);
            }
        }
    }
}
