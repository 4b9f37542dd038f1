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

#include "engine/scene_lights.glsl"

layout(push_constant) uniform LightingConstants {
    mat4 invViewProj;
    vec4 cameraPosition;  // xyz, w specular cube max mip (mips - 1)
    uvec4 size;           // xy output size, z 1: a module composites reflective pixels' specular ambient,
                          // w 1: no direct specular (FrameInputs::directSpecular false: a probe's capture)
} pc;

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
    // The diffuse lobe alone for a capture whose direct specular belongs to no viewer.
    bool diffuseOnly = pc.size.w != 0u;
    vec3 lambert = diffuseColor(baseColor, metallic) * Fd_Lambert();
    uint i = 0u;
    for (; i < kDirectionalLights; ++i) {
        GpuLight light = sceneLight(i);
        vec3 l = -light.directionRange.xyz;
        vec3 f = diffuseOnly ? lambert * max(dot(n, l), 0.0) : evalBRDFCos(n, v, l, baseColor, metallic, roughness);
        s.color += f * light.radiance.rgb * (light.radiance.w > 0.0 ? sunVisibility : 1.0);
    }
    for (; i < kLights; ++i) {
        vec3 l;
        vec3 radiance = incidentRadiance(sceneLight(i), position, l);
        s.color += (diffuseOnly ? lambert * max(dot(n, l), 0.0) : evalBRDFCos(n, v, l, baseColor, metallic, roughness)) *
                   radiance;
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
