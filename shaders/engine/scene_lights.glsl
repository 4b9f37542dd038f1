// The scene's lights and irradiance SH as specialization constants, shared by render.lighting
// (lighting.frag) and every pass that shades a surface again (reflections.cmo_trace shades CMO
// hits for the reflected ray's direction). Constant ids 0 to 287; the host passes
// Renderer::lightingConstants(). Include after lighting_common.glsl.
#ifndef SPECULUM_SCENE_LIGHTS_GLSL
#define SPECULUM_SCENE_LIGHTS_GLSL

#include "common/sh.glsl"

// The scene's lights and irradiance SH never change for a scene, so they are specialization
// constants (ids and packing: lightingConstants() in engine/render/lighting.cpp), not a uniform
// buffer: lavapipe pays for every uniform load in every SIMD group, and constant values let the
// compiler fold what a scene does not use (infinite ranges, spot cones of point lights).
// Measured at 960x540 (gallery): render.lighting 26.5 -> 18.5 ms. The light counts bound the
// loops, which unroll, so each light's constants are indexed by a constant.
layout(constant_id = 0) const uint kDirectionalLights = 0u;  // they come first
layout(constant_id = 1) const uint kLights = 0u;             // all lights

#define SPEC_FLOAT(name, id) layout(constant_id = id) const float name = 0.0;
#define SPEC_VEC3(name, id) SPEC_FLOAT(name##X, id) SPEC_FLOAT(name##Y, (id) + 1) SPEC_FLOAT(name##Z, (id) + 2)
#define SPEC_VEC4(name, id) SPEC_VEC3(name, id) SPEC_FLOAT(name##W, (id) + 3)
#define VEC3_OF(name) vec3(name##X, name##Y, name##Z)
#define VEC4_OF(name) vec4(name##X, name##Y, name##Z, name##W)

// Irradiance SH (9 x rgb) from id 2; light i's four vec4 (GpuLight) from id 32 + 16 i.
#define SPEC_SH(k) SPEC_VEC3(kSH##k, 2 + 3 * k)
SPEC_SH(0) SPEC_SH(1) SPEC_SH(2) SPEC_SH(3) SPEC_SH(4) SPEC_SH(5) SPEC_SH(6) SPEC_SH(7) SPEC_SH(8)
#define SPEC_LIGHT(i) SPEC_VEC4(kLight##i##Pos, 32 + 16 * i) SPEC_VEC4(kLight##i##Dir, 36 + 16 * i) \
    SPEC_VEC4(kLight##i##Rad, 40 + 16 * i) SPEC_VEC4(kLight##i##Cone, 44 + 16 * i)
SPEC_LIGHT(0) SPEC_LIGHT(1) SPEC_LIGHT(2) SPEC_LIGHT(3) SPEC_LIGHT(4) SPEC_LIGHT(5) SPEC_LIGHT(6)
SPEC_LIGHT(7) SPEC_LIGHT(8) SPEC_LIGHT(9) SPEC_LIGHT(10) SPEC_LIGHT(11) SPEC_LIGHT(12)
SPEC_LIGHT(13) SPEC_LIGHT(14) SPEC_LIGHT(15)
#define LIGHT_OF(i) GpuLight(VEC4_OF(kLight##i##Pos), VEC4_OF(kLight##i##Dir), \
    VEC4_OF(kLight##i##Rad), VEC4_OF(kLight##i##Cone))

// Only ever called with a constant i (the unrolled loops), which folds the array away.
GpuLight sceneLight(uint i) {
    GpuLight lights[kMaxLights] = GpuLight[kMaxLights](
        LIGHT_OF(0), LIGHT_OF(1), LIGHT_OF(2), LIGHT_OF(3), LIGHT_OF(4), LIGHT_OF(5), LIGHT_OF(6),
        LIGHT_OF(7), LIGHT_OF(8), LIGHT_OF(9), LIGHT_OF(10), LIGHT_OF(11), LIGHT_OF(12),
        LIGHT_OF(13), LIGHT_OF(14), LIGHT_OF(15));
    return lights[i];
}

vec3 sceneIrradianceSH(vec3 n) {
    vec4 sh[9] = vec4[9](vec4(VEC3_OF(kSH0), 0.0), vec4(VEC3_OF(kSH1), 0.0), vec4(VEC3_OF(kSH2), 0.0),
                         vec4(VEC3_OF(kSH3), 0.0), vec4(VEC3_OF(kSH4), 0.0), vec4(VEC3_OF(kSH5), 0.0),
                         vec4(VEC3_OF(kSH6), 0.0), vec4(VEC3_OF(kSH7), 0.0), vec4(VEC3_OF(kSH8), 0.0));
    return evalSH9(sh, n);
}

// Radiance arriving from a point or spot light (glTF KHR_lights_punctual falloffs); l is set
// to the unit direction towards the light.
vec3 incidentRadiance(GpuLight light, vec3 position, out vec3 l) {
    vec3 toLight = light.positionType.xyz - position;
    float d2 = max(dot(toLight, toLight), 1e-8);
    l = toLight * inversesqrt(d2);
    float attenuation = 1.0 / d2;
    float range = light.directionRange.w;
    if (range > 0.0) {
        float ratio2 = d2 / (range * range);
        float window = clamp(1.0 - ratio2 * ratio2, 0.0, 1.0);
        attenuation *= window * window;
    }
    if (uint(light.positionType.w) == kLightSpot) {
        float cd = dot(light.directionRange.xyz, -l);
        float a = clamp(cd * light.cone.x + light.cone.y, 0.0, 1.0);
        attenuation *= a * a;
    }
    return light.radiance.rgb * attenuation;
}

#endif
