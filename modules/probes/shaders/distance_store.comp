#version 460
#extension GL_GOOGLE_include_directive : require
// probes.distance_store: one face of a local probe's distance cube (probes.glsl, probeSurfaceT):
// per texel of the array's face, the world distance from the capture point to the surface the
// face's camera saw in that texel's direction, 65504 (half's largest) where it saw the sky. The
// texel's direction (the Vulkan cube table, ibl_common.glsl) is projected into the face's camera,
// so the rows' orientation (faceCamera, the store's flip) never enters; a probe below the array's
// size reads its face's pixel under each texel (nearest).
#include "common/camera.glsl"
#include "engine/ibl_common.glsl"
#include "probes/shaders/probe.h"  // kNarrowLobeMaxRoughness

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depthTex;     // the face's depth (nearest), and its G-buffer:
layout(set = 0, binding = 2) uniform sampler2D normalTex;    // xyz normal, w roughness
layout(set = 0, binding = 3) uniform sampler2D albedoTex;    // rgb base colour, a metallic
layout(set = 0, binding = 4) uniform sampler2D emissiveTex;  // a: flags | material << 2
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2DArray outDistance;

layout(push_constant) uniform Push {
    mat4 invViewProj;  // the face's camera
    vec4 eye;          // xyz the capture point
    uvec4 info;        // x the face's size, y the array's face size, z the face (0-5), w the layer of face 0
} pc;

void main() {
    uvec2 texel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(texel, uvec2(pc.info.y)))) return;
    vec3 d = cubeTexelDirection(uvec3(texel, pc.info.z), pc.info.y);
    vec2 uv = projectToUV(pc.eye.xyz + d, inverse(pc.invViewProj));
    ivec2 size = ivec2(pc.info.x);
    ivec2 pixel = clamp(ivec2(uv * vec2(size)), ivec2(0), size - 1);
    float depth = texelFetch(depthTex, pixel, 0).r;
    float dist = 65504.0;
    vec3 mirror = vec3(0.0);
    if (depth > 0.0) {
        dist = min(distance(worldFromDepth(pixelCenterUV(pixel, size), depth, pc.invViewProj), pc.eye.xyz), 65000.0);
        // A smooth reflective metal: its normal times its mean F0, which sampleProbes reflects a
        // ray at (the band its march serves).
        vec4 nr = texelFetch(normalTex, pixel, 0);
        vec4 albedo = texelFetch(albedoTex, pixel, 0);
        uint flags = uint(texelFetch(emissiveTex, pixel, 0).a) & 3u;
        if (flags == 2u && albedo.a >= 0.5 && nr.w < kNarrowLobeMaxRoughness) mirror = normalize(nr.xyz) * dot(albedo.rgb, vec3(1.0 / 3.0));
    }
    imageStore(outDistance, ivec3(texel, int(pc.info.w + pc.info.z)), vec4(dist, mirror));
}
