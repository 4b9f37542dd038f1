// Interface shared by the reflections module's compute shaders (modules/reflections/). Screen
// space here means (x, y) in level-0 pixels (pixel i has its centre at i + 0.5) and z the
// reversed-Z depth value, which is affine along a projected straight line (Uludag 4.4.3), so a
// screen-space ray is a straight line in (x, y, depth).
#ifndef SPECULUM_REFLECTIONS_COMMON_GLSL
#define SPECULUM_REFLECTIONS_COMMON_GLSL

#include "common/brdf.glsl"  // coneTan
#include "common/camera.glsl"

// The frame constants, `rf`: declared once for C++ and GLSL (reflections/frame.h), read from a
// read-only storage buffer, not a uniform block: lavapipe (Mesa 22.3) inlines uniform-block
// values that steer branches and loops, recompiling the shader on every pipeline bind and keeping
// each copy until the pipeline is destroyed -- 0.55 MB a frame with this module (issue 15;
// tests/hardening/driver_probe.cpp shows it in 60 lines). Storage-buffer loads are never inlined.
#include "reflections/shaders/frame.h"

// Per material (index in the G-buffer's flags): mode, roughness scale, roughness override
// (< 0: none), max screen-space roughness.
struct MaterialReflection {
    vec4 params;
};

const uint kFlagUnlit = 1u;
const uint kFlagReflective = 2u;
const uint kMaterialIndexShift = 2u;

// Material modes (scene.hpp ReflectionMode order).
const uint kModeOff = 0u;
const uint kModeScreenSpace = 1u;

// Depth 0 is infinitely far: distances are capped where float still orders them.
float linearDepth(float d) {
    return rfm.znear / max(d, 1e-9);
}

vec3 worldAt(vec2 pixel, float depth) {
    return worldFromDepth(pixel * rf.size.zw, depth, rfm.invViewProj);
}

// Screen-space point (pixels, depth) of a world position in front of the near plane.
vec3 projectToScreen(vec3 world) {
    vec4 clip = rfm.viewProj * vec4(world, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    return vec3(ndcToUV(ndc.xy) * rf.size.xy, ndc.z);
}

// Size of a pyramid level: Vulkan's mip rule, max(1, size >> level). Computed, not queried:
// lavapipe answers textureSize() with one lane's level when lanes ask for different levels.
ivec2 hizLevelSize(int level) {
    return max(ivec2(rf.size.xy) >> level, ivec2(1));
}

// Fades shared by the resolve (weights) and the trace (which skips what they zero).
// cosAway: cosine between the reflected ray and the view direction (< 0 toward the camera).
float cameraFade(float cosAway) {
    float span = rf.cameraFadeStart - rf.cameraFadeEnd;
    return span > 0.0 ? clamp((cosAway - rf.cameraFadeEnd) / span, 0.0, 1.0) : (cosAway >= rf.cameraFadeStart ? 1.0 : 0.0);
}

// dist: world distance from the reflecting point to the hit.
float distanceFade(float dist) {
    float span = rf.distanceFadeEnd - rf.distanceFadeStart;
    return span > 0.0 ? 1.0 - clamp((dist - rf.distanceFadeStart) / span, 0.0, 1.0) : (dist <= rf.distanceFadeStart ? 1.0 : 0.0);
}

// The world distance from which distanceFade is 0.
float distanceFadeEnd() {
    return rf.distanceFadeEnd > rf.distanceFadeStart ? rf.distanceFadeEnd : rf.distanceFadeStart;
}

// Hits near the screen's edges fade to the fallback (reflections.edge_fade).
float edgeFade(vec2 hitPx) {
    vec2 uv = hitPx * rf.size.zw;
    float edge = min(min(uv.x, 1.0 - uv.x), min(uv.y, 1.0 - uv.y));
    return rf.edgeFade > 0.0 ? clamp(edge / rf.edgeFade, 0.0, 1.0) : 1.0;
}

// The full-resolution pixel a half-resolution pixel traces, from its guide (reflections/guide.glsl).
ivec2 guidePixel(ivec2 halfPixel, vec4 guide) {
    int i = (int(abs(guide.w)) - 1) & 3;
    return min(halfPixel * 2 + ivec2(i & 1, i >> 1), ivec2(rf.size.xy) - 1);
}

// brdf.glsl's coneTan is 0 (a mirror's ray: Phong power past 2^20) below roughness 0.03716; a
// ray from this roughness up counts as a cone, a few with no cone among them (the cone variant
// resolves a mirror's ray alike): a compare instead of coneTan's exp2, log2 and square root.
// reflections.classify lists tiles by it; reflections.hit_reuse serves the mirror rays below it.
const float kConeMinRoughness = 0.037;

// method.a for reflections of the sky (resolve.comp writes it, temporal.comp reprojects such
// reflections by direction): the largest half float, exact in the RGBA16F method image.
const float kSkyDistance = 65504.0;

bool finite3(vec3 v) {
    return !any(isnan(v)) && !any(isinf(v));
}

#endif
