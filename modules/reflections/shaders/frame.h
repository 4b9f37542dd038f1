// The reflections module's per-frame constants, declared once for C++ (modules/reflections,
// which fills it) and GLSL (modules/reflections/shaders/common.glsl, which reads it as `rf`), with one
// named field per value. A read-only storage buffer in GLSL (common.glsl says why), std140:
// the matrices and `size` sit at 16-byte boundaries, `znear` fills `eye`'s fourth word, and the
// scalars pack four to a row, which C++ lays out alike (static_asserts in
// modules/reflections/module_impl.hpp).
#ifndef SPECULUM_REFLECTIONS_FRAME_H
#define SPECULUM_REFLECTIONS_FRAME_H

#include "common/host_device.h"

SPECULUM_SHADER_NAMESPACE_BEGIN(speculum::reflections::shader)

// The leading fields, which the shaders also read as the uniform block `rfm` below (one list).
#define SPECULUM_REFLECTION_FRAME_MATRICES \
    mat4 viewProj;                          \
    mat4 invViewProj;                       \
    mat4 prevViewProj;                      \
    mat4 view;                              \
    vec3 eye;                               \
    float znear;

SPECULUM_BLOCK(layout(set = 0, binding = 0, std140) readonly buffer, ReflectionFrame) {
    SPECULUM_REFLECTION_FRAME_MATRICES
    vec4 size;  // width, height, 1 / width, 1 / height
    // Hi-Z and linear tracing.
    float maxIterations;
    float linearPreSteps;
    float hizStartLevel;
    float hizStopLevel;
    float thickness;
    float linearStride;  // px
    float linearMaxSteps;
    float refineSteps;
    // Cones and fades.
    float coneSamples;
    float maxRoughness;  // screen space up to here (below 0: screen space off)
    float envMaxMip;
    float pixelAngle;    // rad / px at the image centre
    float edgeFade;
    float cameraFadeStart;
    float cameraFadeEnd;
    float distanceFadeStart;
    float distanceFadeEnd;
    float debugHizMip;
    float invExposure;
    float traceScale;  // full-resolution pixels per trace pixel per axis: 1 full, 2 half
    // Modes. The trace mode and the debug view are also the trace's and the composite's
    // specialization constants; the shaders read those.
    uint traceMode;     // 0 hiz, 1 linear
    uint coverageMode;  // 0 hit, 1 visibility
    uint historyValid;
    uint hizLevels;
    uint debugView;
    uint multiBounce;
    uint materialCount;
    uint probeCount;  // local probes in the fallback chain
    // Temporal accumulation and stochastic glossy rays.
    float temporalAlpha;  // weight of this frame in the accumulated reflection
    float temporalClip;   // history clipped to mean +- this many standard deviations
    uint frameIndex;      // frames since the module was made (noise decorrelation)
    uint temporalValid;   // the accumulated history and its normals are this frame's previous
    // CMO tracing (reflections.cmo_*; modules/reflections/shaders/cmo_trace.comp).
    uint cmoCount;  // CMOs in the chain (0: off or none)
    float cmoMaxIterations;
    float cmoLinearStep;
    float cmoThickness;
    float cmoMaxDistance;
    float cmoBounces;
    float cmoMaxRoughness;
    uint cmoPassBehind;  // reflections.cmo_unresolved: 1 pass_behind (cmo_trace.comp)
    // Planar probes (modules/probes/shaders/planar.glsl), after screen space, before the CMOs.
    uint planarCount;  // planar probes rendered for this view (0: off or none)
    // reflections.ray_budget=quarter (modules/reflections/shaders/refresh.comp).
    uint refreshValid;  // the refreshed history and its normals are this frame's previous
    uint cameraMoved;   // the view or projection differs from the previous frame's
    // Screen-space hits on reflective surfaces below this roughness are shaded for the ray
    // (reflections.hit_reflect_max_roughness; resolve.comp, mirrorHit).
    float hitReflectMaxRoughness;
    // The planar probes' grounds under the probe step (probes/shaders/ground.glsl).
    uint groundCount;  // 0: off or none
} SPECULUM_BLOCK_INSTANCE(rf);

SPECULUM_SHADER_NAMESPACE_END

#ifndef __cplusplus
// The same buffer's first rows again, as a uniform block (`rfm`, binding 15): the matrices, the
// eye and znear, which the shaders use in arithmetic only, never alone in a branch condition.
// Lavapipe (Mesa 22.3) reads a uniform block's values as constants; a storage buffer's values it
// loads per use, and for these matrices that doubled the module's time at 960x540 (576 ms against
// 362 ms, modules/reflections/MEASUREMENTS.md). Its leak (issue 15) comes from uniform values
// that steer branches, which stay in the storage buffer `rf`: hardening.memory_flat guards it.
layout(set = 0, binding = 15, std140) uniform ReflectionMatrices {
    SPECULUM_REFLECTION_FRAME_MATRICES
} rfm;
#endif

#endif
