#version 460
#extension GL_GOOGLE_include_directive : require
// One level of the radiance cube's box-filtered mip chain, the source that the prefilter reads
// with filtered importance sampling. A texel centre of level m + 1 is the shared corner of four
// texels of level m on the same face, so one bilinear lookup is their exact 2x2 average. RGBA:
// a local probe's radiance is premultiplied by its coverage (alpha 0 where it saw the sky).
#include "engine/ibl_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(set = 0, binding = 0) uniform samplerCube source;  // the single level m
layout(set = 0, binding = 1, rgba16f) writeonly uniform imageCube target;

layout(push_constant) uniform Push {
    uint size;  // face size of level m + 1
} pc;

void main() {
    uvec3 texel = gl_GlobalInvocationID;
    if (texel.x >= pc.size || texel.y >= pc.size) return;
    vec3 d = cubeTexelDirection(texel, pc.size);
    // Alpha is carried: a probe's coverage by geometry (1 for the sky's own cube).
    imageStore(target, ivec3(texel), textureLod(source, d, 0.0));
}
