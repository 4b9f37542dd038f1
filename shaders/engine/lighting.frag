#version 460
#extension GL_GOOGLE_include_directive : require
// render.lighting: a fullscreen fragment pass (fullscreen.vert) reads the G-buffer and writes HDR
// radiance into the colour attachment (lavapipe stores attachment tiles far faster than imageStore).
#include "common/brdf.glsl"
#include "common/camera.glsl"
#include "common/sh.glsl"
#include "engine/lighting_common.glsl"

layout(set = 0, binding = 0) uniform sampler2D depthTex;     // D32 reversed-Z, texelFetch only
layout(set = 0, binding = 1) uniform sampler2D albedoTex;
layout(set = 0, binding = 2) uniform sampler2D normalTex;
layout(set = 0, binding = 3) uniform sampler2D emissiveTex;
layout(set = 0, binding = 4) uniform sampler2D shadowMask;   // R8 sun visibility (shadow_mask.frag)
layout(set = 0, binding = 5) uniform samplerCube envSpecular;
layout(set = 0, binding = 6) uniform sampler2D envDFG;
layout(location = 0) out vec4 outLinear;

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

layout(push_constant) uniform LightingConstants {
    mat4 invViewProj;
    vec4 cameraPosition;  // xyz, w specular cube max mip (mips - 1)
    uvec4 size;           // xy output size, z 1: a module composites reflective pixels' specular ambient
} pc;

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

// Image-based specular ambient (split-sum: GGX-prefiltered environment times the DFG scale and
// bias). The reflections module replaces exactly this term for reflective pixels. Returns the
// scale; the caller looks up the environment along r at lod (one lookup shared with the sky).
vec3 iblSpecularWeight(vec3 n, vec3 v, float perceptualRoughness, vec3 f0, out vec3 r,
                       out float lod) {
    r = reflect(-v, n);
    lod = perceptualRoughness * pc.cameraPosition.w;
    float NoV = clamp(dot(n, v), 0.0, 1.0);
    vec2 dfg = textureLod(envDFG, vec2(NoV, perceptualRoughness), 0.0).rg;
    return f0 * dfg.x + dfg.y;
}

vec3 iblDiffuseAmbient(vec3 n, vec3 diffuse) {
    return diffuse * sceneIrradianceSH(n);
}

struct Shaded {
    vec3 color;      // all but the specular ambient
    vec3 envWeight;  // times the environment along envDir at envLod
    vec3 envDir;
    float envLod;
};

// v: unit direction towards the eye.
Shaded shadeSurface(ivec2 pixel, vec3 position, vec3 v) {
    vec4 albedo = texelFetch(albedoTex, pixel, 0);
    vec4 normalRough = texelFetch(normalTex, pixel, 0);
    vec3 n = normalize(normalRough.xyz);
    float roughness = normalRough.w;
    vec3 baseColor = albedo.rgb;
    float metallic = albedo.a;

    Shaded s;
    s.color = vec3(0.0);
    float sunVisibility = texelFetch(shadowMask, pixel, 0).r;
    // No early-outs per pixel: a SIMD CPU driver pays for masked lanes anyway.
    uint i = 0u;
    for (; i < kDirectionalLights; ++i) {
        GpuLight light = sceneLight(i);
        vec3 f = evalBRDFCos(n, v, -light.directionRange.xyz, baseColor, metallic, roughness);
        s.color += f * light.radiance.rgb * (light.radiance.w > 0.0 ? sunVisibility : 1.0);
    }
    for (; i < kLights; ++i) {
        vec3 l;
        vec3 radiance = incidentRadiance(sceneLight(i), position, l);
        s.color += evalBRDFCos(n, v, l, baseColor, metallic, roughness) * radiance;
    }
    s.color += iblDiffuseAmbient(n, diffuseColor(baseColor, metallic));
    s.envWeight = iblSpecularWeight(n, v, roughness, specularF0(baseColor, metallic), s.envDir,
                                    s.envLod);
    return s;
}

// Sky, unlit and lit pixels share one straight path: a SIMD CPU driver (lavapipe) runs both
// sides of a per-pixel branch anyway, so the sky and the specular ambient share one cube
// lookup instead of paying for two.
void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec2 uv = pixelCenterUV(pixel, ivec2(pc.size.xy));
    float depth = texelFetch(depthTex, pixel, 0).r;
    bool sky = depth <= 0.0;
    // Depth 0 has no finite position: the sky takes the ray's direction from a point at 0.5,
    // as viewRayDirection does. The near-plane point makes v right for orthographic views too.
    vec3 position = worldFromDepth(uv, sky ? 0.5 : depth, pc.invViewProj);
    vec3 v = normalize(worldFromDepth(uv, 1.0, pc.invViewProj) - position);
    Shaded s = shadeSurface(pixel, position, v);
    vec3 env = textureLod(envSpecular, sky ? -v : s.envDir, sky ? 0.0 : s.envLod).rgb;
    vec4 emissive = texelFetch(emissiveTex, pixel, 0);
    uint flags = uint(emissive.a);
    bool unlit = (flags & 1u) != 0u;  // the base colour, untouched
    // The reflections module replaces exactly this term for reflective pixels (kFlagReflective).
    float envScale = (pc.size.z != 0u && (flags & 2u) != 0u) ? 0.0 : 1.0;
    vec3 color = sky ? env : unlit ? emissive.rgb : emissive.rgb + s.color + env * s.envWeight * envScale;
    outLinear = vec4(color, 1.0);
}
