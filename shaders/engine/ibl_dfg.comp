#version 460
#extension GL_GOOGLE_include_directive : require
// The split-sum DFG table (Karis 2013): for N.V = x and perceptual roughness = y (texel
// centres), the scale and bias of F0 in the directional albedo
//   integral of D * V_SmithGGXCorrelated * F_Schlick * NdotL over L = F0 * scale + bias,
// estimated with GGX importance sampling of the half vector.
#include "engine/ibl_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

// No format qualifier: rg16f storage needs shaderStorageImageExtendedFormats, while writing
// without a format (shaderStorageImageWriteWithoutFormat) is enabled wherever supported.
layout(set = 0, binding = 0) writeonly uniform image2D dfg;

layout(push_constant) uniform Push {
    uint size;
    uint samples;
} pc;

void main() {
    uvec2 texel = gl_GlobalInvocationID.xy;
    if (texel.x >= pc.size || texel.y >= pc.size) return;
    float NdotV = (float(texel.x) + 0.5) / float(pc.size);
    float roughness = (float(texel.y) + 0.5) / float(pc.size);
    float alpha = roughness * roughness;
    vec3 v = vec3(sqrt(1.0 - NdotV * NdotV), 0.0, NdotV);

    vec2 sum = vec2(0.0);
    for (uint i = 0u; i < pc.samples; ++i) {
        vec3 h = importanceSampleGGX(hammersley(i, pc.samples), alpha);
        float VdotH = dot(v, h);
        vec3 l = 2.0 * VdotH * h - v;
        float NdotL = l.z;
        if (NdotL <= 0.0 || VdotH <= 0.0) continue;
        float NdotH = h.z;
        // D cancels against the pdf D * NdotH / (4 VdotH).
        float gVis = V_SmithGGXCorrelated(NdotV, NdotL, alpha) * 4.0 * NdotL * VdotH / NdotH;
        float fc = pow(1.0 - VdotH, 5.0);
        sum += vec2(1.0 - fc, fc) * gVis;
    }
    imageStore(dfg, ivec2(texel), vec4(sum / float(pc.samples), 0.0, 0.0));
}
