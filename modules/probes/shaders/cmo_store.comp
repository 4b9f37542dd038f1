#version 460
#extension GL_GOOGLE_include_directive : require
// probes.cmo_store: one face of a CMO from its capture (the renderer's passes and
// probes.capture_bounce at the CMO's resolution) into the CMO arrays, rows flipped as every cube
// face is stored (probes::faceCamera): the lit radiance with the sun's visibility, the mirror
// mask and the reflective flag in alpha (visibility + 2 * mirror + 4 * reflective: cmo.glsl's
// cmoUnpackFlags), the world distance to the CMO's centre (level 0 of
// the min/max hierarchy, both channels; the sky at SPECULUM_CMO_SKY_DISTANCE), and the
// attributes reflections.cmo_trace shades a hit with for the reflected ray's direction.
#include "common/camera.glsl"
#include "probes/shaders/cmo.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depthTex;
layout(set = 0, binding = 1) uniform sampler2D albedoTex;    // rgb base colour, a metallic
layout(set = 0, binding = 2) uniform sampler2D normalTex;    // xyz normal, w roughness
layout(set = 0, binding = 3) uniform sampler2D emissiveTex;  // a: flags | material << 2
layout(set = 0, binding = 4) uniform sampler2D faceTex;      // lit, with the bounce
layout(set = 0, binding = 5) uniform sampler2D shadowMask;   // R8 sun visibility
layout(set = 0, binding = 6, std430) readonly buffer MirrorTable {
    float mirror[];  // per material index: 1 when it is a mirror for self-reflections
};
layout(set = 0, binding = 7, rgba16f) uniform writeonly image2D outRadiance;
layout(set = 0, binding = 8, rg32f) uniform writeonly image2D outDistance;
layout(set = 0, binding = 9, rgba16f) uniform writeonly image2D outAttr;
layout(set = 0, binding = 10, rgba8) uniform writeonly image2D outAlbedo;

layout(push_constant) uniform Push {
    mat4 invViewProj;
    vec4 center;  // xyz the CMO's centre
    uvec4 info;   // x face size, y mirror table size, z 1: a shadow mask is bound (else the sun is unshadowed)
} pc;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    int n = int(pc.info.x);
    if (any(greaterThanEqual(texel, ivec2(n)))) return;
    ivec2 pixel = ivec2(texel.x, n - 1 - texel.y);
    float depth = texelFetch(depthTex, pixel, 0).r;
    uint flags = uint(texelFetch(emissiveTex, pixel, 0).a);
    float d = SPECULUM_CMO_SKY_DISTANCE;
    if (depth > 0.0) {
        vec3 p = worldFromDepth((vec2(pixel) + 0.5) / float(n), depth, pc.invViewProj);
        d = length(p - pc.center.xyz);
    }
    uint material = min(flags >> 2u, max(pc.info.y, 1u) - 1u);
    bool reflective = depth > 0.0 && (flags & 2u) != 0u && (flags & 1u) == 0u;
    bool isMirror = reflective && mirror[material] > 0.5;
    float sun = mix(1.0, texelFetch(shadowMask, pixel, 0).r, float(min(pc.info.z, 1u)));
    imageStore(outRadiance, texel,
               vec4(texelFetch(faceTex, pixel, 0).rgb, sun + (isMirror ? 2.0 : 0.0) + (reflective ? 4.0 : 0.0)));
    imageStore(outDistance, texel, vec4(d, d, 0.0, 0.0));
    imageStore(outAttr, texel, texelFetch(normalTex, pixel, 0));
    imageStore(outAlbedo, texel, texelFetch(albedoTex, pixel, 0));
}
