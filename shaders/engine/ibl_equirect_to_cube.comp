#version 460
#extension GL_GOOGLE_include_directive : require
// Cube mip 0 from the equirectangular sky: a bilinear lookup along each texel-centre direction
// (or the mean of a grid of them when the sky is finer than the cube),
// written both to the radiance cube (the source of the filtered mip chain) and to mip 0 of the
// specular cube (the mirror image). Sky convention: environment.hpp.
#include "engine/ibl_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(set = 0, binding = 0, std430) readonly buffer Equirect { float rgb[]; } equirect;
layout(set = 0, binding = 1, rgba16f) writeonly uniform imageCube radianceCube;
layout(set = 0, binding = 2, rgba16f) writeonly uniform imageCube specularCube;

layout(push_constant) uniform Push {
    uint width;
    uint height;
    uint cubeSize;
    float scale;
    uint supersample;  // n x n lookups per texel
} pc;

const float HALF_MAX = 65504.0;

vec3 fetch(int x, int y) {
    x = (x % int(pc.width) + int(pc.width)) % int(pc.width);  // wrap in u
    y = clamp(y, 0, int(pc.height) - 1);                       // clamp in v
    uint i = 3u * (uint(y) * pc.width + uint(x));
    return vec3(equirect.rgb[i], equirect.rgb[i + 1u], equirect.rgb[i + 2u]);
}

vec3 sampleEquirect(vec3 d) {
    // v = acos(d.y) / pi written as an atan: Vulkan allows acos a loose precision (lavapipe's is
    // off by ~1e-3 rad), which shifted whole rows against the CPU reference.
    vec2 uv = vec2(0.5 + atan(d.x, -d.z) / (2.0 * PI), atan(length(d.xz), d.y) / PI);
    vec2 p = uv * vec2(pc.width, pc.height) - 0.5;
    vec2 p0 = floor(p);
    vec2 f = p - p0;
    int x = int(p0.x);
    int y = int(p0.y);
    vec3 top = mix(fetch(x, y), fetch(x + 1, y), f.x);
    vec3 bottom = mix(fetch(x, y + 1), fetch(x + 1, y + 1), f.x);
    return mix(top, bottom, f.y);
}

void main() {
    uvec3 texel = gl_GlobalInvocationID;
    if (texel.x >= pc.cubeSize || texel.y >= pc.cubeSize) return;
    // A sky much finer than the cube is averaged over an n x n grid inside the texel, so a small
    // bright sun keeps its energy instead of aliasing in or out; n = 1 is the texel centre.
    vec3 radiance = vec3(0.0);
    for (uint j = 0u; j < pc.supersample; ++j)
        for (uint i = 0u; i < pc.supersample; ++i) {
            vec2 st = vec2(texel.xy) + (vec2(i, j) + 0.5) / float(pc.supersample);
            radiance += sampleEquirect(cubeDirection(texel.z, st / float(pc.cubeSize)));
        }
    radiance *= pc.scale / float(pc.supersample * pc.supersample);
    radiance = min(radiance, HALF_MAX);  // inf in a half float would spread through every mip
    imageStore(radianceCube, ivec3(texel), vec4(radiance, 1.0));
    imageStore(specularCube, ivec3(texel), vec4(radiance, 1.0));
}
