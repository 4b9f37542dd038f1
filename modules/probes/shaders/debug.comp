#version 460
#extension GL_GOOGLE_include_directive : require
// probes.debug: what the probes do per pixel, replacing the image (probes.debug_view).
//   influence: the blend, each probe in its own colour weighted by its share, the sky's share
//              dark blue (the weights the fallback chain uses before coverage and screen space);
//   winner:    the colour of the probe with the largest share, brighter the larger it is; dark
//              blue where the sky takes everything.
// Palette: probe i (blend order) is 0.5 + 0.5 cos(2 pi (i * 0.618 + (0, 1/3, 2/3))).
#define PROBES_BUFFER_BINDING 2
#define PROBES_CUBES_BINDING 3
#include "common/camera.glsl"
#include "probes/shaders/probes.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(constant_id = 0) const uint kView = 1u;  // 1 influence, 2 winner

layout(set = 0, binding = 0) uniform sampler2D depthTex;
layout(set = 0, binding = 1) uniform sampler2D normalTex;
layout(set = 0, binding = 4, rgba16f) uniform writeonly image2D outImage;

layout(push_constant) uniform Push {
    mat4 invViewProj;
    vec4 eye;    // xyz camera, w 1 / exposure (debug colours reach the screen near their value)
    uvec4 info;  // xy size, z probe count, w 0
} pc;

const vec3 kSky = vec3(0.02, 0.03, 0.25);

vec3 probeColour(uint i) {
    return 0.5 + 0.5 * cos(6.2831853 * (float(i) * 0.618034 + vec3(0.0, 1.0 / 3.0, 2.0 / 3.0)));
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.info.xy))) return;
    float depth = texelFetch(depthTex, pixel, 0).r;
    vec3 colour = vec3(0.0);
    if (depth > 0.0) {
        vec3 p = worldFromDepth((vec2(pixel) + 0.5) / vec2(pc.info.xy), depth, pc.invViewProj);
        vec3 n = normalize(texelFetch(normalTex, pixel, 0).xyz);
        float total = 0.0, best = 0.0;
        uint winner = 0xffffffffu;
        vec3 blend = vec3(0.0);
        for (uint i = 0u; i < pc.info.z; ++i) {
            // The blend's weights, as sampleProbes takes them.
            float w = max(min(probeInfluence(probes[i], p, n), 1.0 - total), 0.0);
            blend += w * probeColour(i);
            winner = w > best ? i : winner;
            best = max(best, w);
            total += w;
        }
        colour = kView == 1u ? blend + (1.0 - total) * kSky
                             : (winner == 0xffffffffu ? kSky : probeColour(winner) * (0.35 + 0.65 * best));
    }
    imageStore(outImage, pixel, vec4(colour * pc.eye.w, 1.0));
}
