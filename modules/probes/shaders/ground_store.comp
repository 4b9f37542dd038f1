#version 460
#extension GL_GOOGLE_include_directive : require
// probes.ground_store: a planar probe's ground (probe.h, PlanarGround) from its orthographic view
// straight down: rgb the lit surface with its specular ambient (probes.capture_bounce) less its
// direct specular, premultiplied by a coverage that is 1 where the texel sees a dielectric surface
// lying in the plane (its normal within the planar probe's 18 degrees), a metal's marker where a
// metal lies in it (below), and 0 elsewhere: the sky, and the tops of the objects that stand on
// the plane and reach into the view's 2 cm slab around it. A lookup gives the uncovered share to
// the probes' proxy, as a cube's alpha does (probes.glsl).
//
// The direct specular goes because it belongs to the view straight down: a lamp's highlight lies
// under the lamp there, and a ray meeting the floor at another angle sees it elsewhere or not at
// all. Kept, it lit the gallery's chrome torus white where its rays met the floor under a lamp
// (gallery.floor_grazing, mirror band 22.4 -> 21.6 dB).
#include "common/brdf.glsl"
#include "common/camera.glsl"
#include "engine/lighting_common.glsl"
#include "engine/scene_lights.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depthTex;
layout(set = 0, binding = 1) uniform sampler2D albedoTex;   // rgb base colour, a metallic
layout(set = 0, binding = 2) uniform sampler2D normalTex;   // xyz normal, w roughness
layout(set = 0, binding = 3) uniform sampler2D faceTex;     // probes.capture_bounce: alpha 0 at the sky
layout(set = 0, binding = 4) uniform sampler2D shadowMask;  // sun visibility (info.z 1), else unread
layout(set = 0, binding = 5, rgba16f) uniform writeonly image2D outImage;

layout(push_constant) uniform Push {
    mat4 invViewProj;
    vec4 plane;  // xyz unit normal, w offset
    vec4 params; // x the cosine of the normal tolerance, yzw 0
    uvec4 info;  // xy the image's size, z 1: a shadowed directional light (shadowMask)
} pc;

// The direct specular render.lighting added for view direction v (evalBRDFCos less its diffuse).
vec3 directSpecular(vec3 p, vec3 n, vec3 v, vec4 albedo, float roughness, float sun) {
    vec3 f0 = specularF0(albedo.rgb, albedo.a);
    float alpha = roughnessToAlpha(roughness);
    vec3 sum = vec3(0.0);
    uint i = 0u;
    for (; i < kDirectionalLights; ++i) {
        GpuLight light = sceneLight(i);
        vec3 l = -light.directionRange.xyz;
        sum += specularBRDFCos(n, v, l, f0, alpha) * light.radiance.rgb * (light.radiance.w > 0.0 ? sun : 1.0);
    }
    for (; i < kLights; ++i) {
        vec3 l;
        vec3 radiance = incidentRadiance(sceneLight(i), p, l);
        sum += specularBRDFCos(n, v, l, f0, alpha) * radiance;
    }
    return sum;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.info.xy))) return;
    float depth = texelFetch(depthTex, pixel, 0).r;
    vec4 nr = texelFetch(normalTex, pixel, 0);
    vec3 n = normalize(nr.xyz);
    vec4 face = texelFetch(faceTex, pixel, 0);
    vec4 albedo = texelFetch(albedoTex, pixel, 0);
    // A metal's radiance is all reflection, which depends on the ray's direction: seen from straight
    // above, the gallery's mirror floor showed the sky (the first bake's) where the concave
    // mirror's rays met it, and its share of gross errors rose from 2.7% to 6.7% of the view's
    // pixels. The probes' capture of a metal floor is no better a guess but no worse, so a metal
    // leaves the ground's coverage to them; a dielectric floor is mostly its diffuse light. A
    // metal's texel holds its F0 instead, marked by a coverage of -1 minus its roughness: on a
    // floor, probes.capture_bounce reflects the ray off it (metalGround). Box mips average a
    // marker with its neighbours; only a texel at -1 or below (metal throughout) counts as one, a
    // mixed one as no coverage.
    bool inPlane = depth > 0.0 && face.a > 0.0 && dot(n, pc.plane.xyz) >= pc.params.x;
    bool metal = albedo.a >= 0.5;
    bool onPlane = inPlane && !metal;
    vec4 result = vec4(0.0);
    if (inPlane && metal) result = vec4(specularF0(albedo.rgb, albedo.a), -1.0 - nr.w);
    if (onPlane) {
        vec2 uv = pixelCenterUV(pixel, ivec2(pc.info.xy));
        vec3 p = worldFromDepth(uv, depth, pc.invViewProj);
        // render.lighting's v for an orthographic view: toward the near plane along the view ray.
        vec3 v = normalize(worldFromDepth(uv, 1.0, pc.invViewProj) - p);
        float sun = pc.info.z != 0u ? texelFetch(shadowMask, pixel, 0).r : 1.0;
        vec3 spec = directSpecular(p, n, v, albedo, nr.w, sun);
        result = vec4(max(face.rgb - spec, vec3(0.0)), 1.0);
    }
    imageStore(outImage, pixel, result);
}
