// Interface shared by the reflections module's compute shaders (modules/reflections/). Screen
// space here means (x, y) in level-0 pixels (pixel i has its centre at i + 0.5) and z the
// reversed-Z depth value, which is affine along a projected straight line (Uludag 4.4.3), so a
// screen-space ray is a straight line in (x, y, depth).
#ifndef SPECULUM_REFLECTIONS_COMMON_GLSL
#define SPECULUM_REFLECTIONS_COMMON_GLSL

#include "common/camera.glsl"

// std140 twin of FrameUniforms in modules/reflections/passes.hpp. A read-only storage buffer, not
// a uniform block: lavapipe (Mesa 22.3) inlines uniform-block values that steer branches and
// loops, recompiling the shader on every pipeline bind and keeping each copy until the pipeline
// is destroyed -- 0.55 MB a frame with this module (issue 15; tests/hardening/driver_probe.cpp
// shows it in 60 lines). Storage-buffer loads are never inlined.
layout(set = 0, binding = 0, std140) readonly buffer ReflectionFrame {
    mat4 viewProj;
    mat4 invViewProj;
    mat4 prevViewProj;
    mat4 view;
    vec4 camera;    // xyz eye, w znear
    vec4 size;      // width, height, 1 / width, 1 / height
    vec4 trace;     // max iterations, linear pre-steps, Hi-Z start level, Hi-Z stop level
    vec4 trace2;    // thickness, linear stride (px), linear max steps, refine steps
    vec4 cone;      // cone samples, max roughness, environment max mip, pixel angle (rad / px)
    vec4 fade;      // edge fade, camera fade start, camera fade end, distance fade start
    vec4 fade2;     // distance fade end, debug Hi-Z mip, 0, 0
    // The trace mode and the debug view are also the trace's and the composite's specialization
    // constants; the shaders read those.
    uvec4 modes;    // trace mode (0 hiz, 1 linear), coverage (0 hit, 1 visibility), history valid, Hi-Z levels
    uvec4 modes2;   // debug view, multi-bounce, material count, local probe count
} rf;

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
    return rf.camera.w / max(d, 1e-9);
}

vec3 worldAt(vec2 pixel, float depth) {
    return worldFromDepth(pixel * rf.size.zw, depth, rf.invViewProj);
}

// Screen-space point (pixels, depth) of a world position in front of the near plane.
vec3 projectToScreen(vec3 world) {
    vec4 clip = rf.viewProj * vec4(world, 1.0);
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
    float span = rf.fade.y - rf.fade.z;
    return span > 0.0 ? clamp((cosAway - rf.fade.z) / span, 0.0, 1.0) : (cosAway >= rf.fade.y ? 1.0 : 0.0);
}

// dist: world distance from the reflecting point to the hit.
float distanceFade(float dist) {
    float span = rf.fade2.x - rf.fade.w;
    return span > 0.0 ? 1.0 - clamp((dist - rf.fade.w) / span, 0.0, 1.0) : (dist <= rf.fade.w ? 1.0 : 0.0);
}

// The world distance from which distanceFade is 0.
float distanceFadeEnd() {
    return rf.fade2.x > rf.fade.w ? rf.fade2.x : rf.fade.w;
}

bool finite3(vec3 v) {
    return !any(isnan(v)) && !any(isinf(v));
}

#endif
