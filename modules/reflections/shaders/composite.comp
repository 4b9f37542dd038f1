#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.composite: adds the reflection times the split-sum DFG term (F0 * A + B) to the
// lit image on reflective pixels (render.lighting left their specular ambient out), or draws
// the selected debug view instead.
//
// Work follows need (issue 23): with reflections.tiles and no debug view it runs only on the
// tiles that reflect (the resolve's ray and lookup lists, tiles.h), each workgroup taking an 8x8
// block of a tile's full-resolution footprint (kTileScale x kTileScale blocks at half resolution),
// after reflections.composite_copy has copied the lit image into its outputs whole: every other
// pixel's result is the lit image as it is (render.lighting writes alpha 1, as this pass does).
// A tile is in those lists when any of its trace pixels reflects, and at half resolution a trace
// pixel reflects when any of its 2x2 does (guide.glsl: reflective pixels first), so no reflective
// pixel is left out.
// (Fusing the half-resolution upsampling in here was measured and dropped: on the gallery, 90%
// reflective, the fused pass cost 39 ms against 18 + 20 for the two; MEASUREMENTS, issue 23.)
#include "common/brdf.glsl"
#include "reflections/shaders/common.glsl"
#include "reflections/shaders/material.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D litTex;
layout(set = 0, binding = 2) uniform sampler2D albedoTex;   // rgb base colour, a metallic
layout(set = 0, binding = 3) uniform sampler2D normalTex;
layout(set = 0, binding = 5) uniform sampler2D emissiveTex;
layout(set = 0, binding = 6) uniform sampler2D reflectionTex;
layout(set = 0, binding = 7) uniform sampler2D dfgTex;      // linear clamp
layout(set = 0, binding = 8) uniform sampler2D hiz;         // texelFetch
layout(set = 0, binding = 9) uniform sampler2D hitTex;      // texelFetch
layout(set = 0, binding = 10) uniform sampler2D debugTex;  // the debug view's input: method weights or CMO info
layout(set = 0, binding = 11, rgba16f) uniform writeonly image2D dst;
// With a debug view or temporal accumulation: the image that feeds the next frame's colour
// pyramid (reflections of reflections): without the debug view, and with this frame's own
// reflection rather than the accumulated one. An accumulated reflection in that loop would lag
// every bounce by the accumulation's time constant, one more per bounce: a still camera took
// 16 frames and more to converge (tests/stability/stability_test.py converge).
layout(set = 0, binding = 12, rgba16f) uniform writeonly image2D plainOut;
layout(set = 0, binding = 13) uniform sampler2D rawReflectionTex;  // temporal: this frame's

// reflections.debug_view (DebugView): a specialization constant, so that the plain composite
// carries none of the debug views' fetches (lavapipe runs both sides of a uniform branch).
layout(constant_id = 0) const uint kDebugView = 0u;
// The tile lists (reflections.classify): the tiles debug view reads each tile's arrival word.
#include "reflections/shaders/tiles.glsl"
// reflections.temporal: reflectionTex is the accumulated reflection, rawReflectionTex this frame's.
layout(constant_id = 1) const uint kTemporal = 0u;
// Full-resolution pixels per trace pixel along an axis (2 at half resolution): a tile's footprint.
layout(constant_id = 2) const uint kTileScale = 1u;
// The list this pipeline takes its tiles from (kTileModeWork only): a specialization constant,
// not a push constant, as every tiled pass's (lavapipe compiles a shader again for each new
// push-constant value it can fold in: two lists a frame cost this pass a third of its time).
layout(constant_id = 3) const uint kList = 0u;

vec3 heat(float x) {
    x = clamp(x, 0.0, 1.0);
    return clamp(vec3(1.5 - abs(4.0 * x - 3.0), 1.5 - abs(4.0 * x - 2.0), 1.5 - abs(4.0 * x - 1.0)), 0.0, 1.0);
}

vec3 debugView(uint view, ivec2 pixel, bool reflective, vec3 lit) {
    vec3 dim = vec3(dot(lit, vec3(0.2126, 0.7152, 0.0722)) * 0.15);
    // The trace's image is at trace resolution (half: a pixel per 2x2).
    vec4 hit = texelFetch(hitTex, ivec2(vec2(pixel) / rf.traceScale), 0);
    if (view == 1u) return reflective ? heat(hit.w / max(rf.maxIterations, 1.0)) : dim;
    if (view == 2u) return reflective ? (hit.z > 0.0 ? vec3(0.1, 0.9, 0.1) : vec3(0.9, 0.1, 0.1)) : dim;
    if (view == 3u) return reflective ? vec3(texelFetch(reflectionTex, pixel, 0).a) : dim;
    if (view == 4u) {
        // r screen space, g probes, b sky, CMOs yellow.
        vec4 w = texelFetch(debugTex, pixel, 0);
        return reflective ? w.rgb + vec3(w.a, w.a, 0.0) : dim;
    }
    if (view == 7u) {
        // CMO tracing (reflections.cmo_info, trace size): hue by the CMO that hit, brightness by
        // iterations; red: unresolved by every CMO; dark: not traced or a miss.
        vec4 info = texelFetch(debugTex, ivec2(vec2(pixel) / rf.traceScale), 0);
        const vec3 hues[4] = vec3[](vec3(0.2, 0.9, 0.3), vec3(0.3, 0.5, 1.0), vec3(1.0, 0.8, 0.2), vec3(0.9, 0.3, 0.9));
        float bright = 0.35 + 0.65 * clamp(info.x / max(rf.cmoMaxIterations * 0.25, 1.0), 0.0, 1.0);
        if (!reflective) return dim;
        if (info.z > 1.5) return vec3(0.9, 0.1, 0.1);
        if (info.z > 0.5) return hues[(int(info.y) - 1) & 3] * bright;
        return vec3(0.05);
    }
    if (view == 8u) {
        // The tile's needs as classify gathered them (tiles.glsl's tileNeeds).
        ivec2 traceSize = ivec2(ceil(rf.size.xy / rf.traceScale));
        ivec2 tile = ivec2(vec2(pixel) / rf.traceScale) / int(kTileSize);
        int tilesX = (traceSize.x + int(kTileSize) - 1) / int(kTileSize);
        uint word = tiles.entries[uint(tile.y * tilesX + tile.x) * kTileLists + kListArrivals];
        uint needs = tileNeeds(word);
        bool ray = (needs & kNeedRay) != 0u, cmo = (needs & kNeedCmo) != 0u;
        vec3 c = ray ? (cmo ? vec3(0.9, 0.8, 0.1) : vec3(0.1, 0.8, 0.2)) : (cmo ? vec3(0.8, 0.2, 0.8) : vec3(0.15, 0.3, 0.9));
        // The resolve's lighter variants (tiles.h): rays without a cone lighter, lookups with
        // no narrow lobe darker.
        if (ray && (needs & kNeedCone) == 0u) c = mix(c, vec3(1.0), 0.5);
        if (!ray && (needs & kNeedNarrow) == 0u) c *= 0.5;
        return reflective ? c : dim;
    }
    if (view == 5u) {
        int level = min(int(rf.debugHizMip), int(rf.hizLevels) - 1);
        ivec2 cell = min(pixel >> level, hizLevelSize(level) - 1);
        vec2 mm = texelFetch(hiz, cell, level).rg;
        // log2 distance over 2^-2 .. 2^8 m: near is red, far is blue; x farthest, y closest.
        float closest = (log2(linearDepth(mm.y)) + 2.0) / 10.0;
        float farthest = (log2(linearDepth(mm.x)) + 2.0) / 10.0;
        return heat(1.0 - closest) * (((pixel.x >> level) + (pixel.y >> level)) % 2 == 0 ? 1.0 : 0.85) *
               (abs(farthest - closest) > 0.05 ? 0.6 : 1.0);
    }
    return texelFetch(reflectionTex, pixel, 0).rgb;
}

void compositePixel(ivec2 pixel) {
    vec3 lit = texelFetch(litTex, pixel, 0).rgb;
    float depth;
    vec4 normalRough;
    PixelMaterial m = readSurface(hiz, normalTex, emissiveTex, pixel, depth, normalRough);
    bool reflective = depth > 0.0 && m.reflective;
    vec3 color = lit;
    vec3 plain = lit;
    if (reflective) {
        vec4 albedo = texelFetch(albedoTex, pixel, 0);
        vec3 p = worldAt(vec2(pixel) + 0.5, depth);
        vec3 v = normalize(rfm.eye - p);
        float NoV = clamp(dot(normalize(normalRough.xyz), v), 0.0, 1.0);
        vec2 dfg = textureLod(dfgTex, vec2(NoV, m.roughness), 0.0).rg;
        vec3 f0 = specularF0(albedo.rgb, albedo.a);
        vec3 specular = f0 * dfg.x + dfg.y;
        color = lit + texelFetch(reflectionTex, pixel, 0).rgb * specular;
        plain = kTemporal != 0u ? lit + texelFetch(rawReflectionTex, pixel, 0).rgb * specular : color;
    }
    if (kDebugView != 0u || kTemporal != 0u) imageStore(plainOut, pixel, vec4(plain, 1.0));
    // Debug colours are divided by the exposure so that they reach the screen near their value.
    if (kDebugView != 0u) color = debugView(kDebugView, pixel, reflective, lit) * rf.invExposure;
    imageStore(dst, pixel, vec4(color, 1.0));
}

void main() {
    ivec2 size = ivec2(rf.size.xy);
    if (kTileMode == kTileModeScreen) {
        ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
        if (all(lessThan(pixel, size))) compositePixel(pixel);
        return;
    }
    // A workgroup per 8x8 block of the tile's footprint (gl_WorkGroupID.y: the block; 0 at full
    // resolution, 0-3 at half from reflections.footprint_args).
    ivec2 pixel = footprintBlockPixel(kList, kTileScale);
    if (all(lessThan(pixel, size))) compositePixel(pixel);
}
