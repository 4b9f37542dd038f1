#version 460
#extension GL_GOOGLE_include_directive : require
// One mip of the specular cube: the split-sum GGX prefilter (N = V = R) for one roughness,
// with GGX importance sampling and filtered importance sampling (Krivanek & Colbert 2008,
// Karis 2013): each sample reads the radiance cube's box mip whose texel solid angle matches
// the sample's share of the lobe, so a few dozen samples give a smooth, alias-free result.
#include "engine/ibl_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
const uint GROUP = 64u;

layout(set = 0, binding = 0) uniform samplerCube radiance;  // all box mips
layout(set = 0, binding = 1, rgba16f) writeonly uniform imageCube target;

layout(push_constant) uniform Push {
    uint size;         // face size of the target mip
    uint samples;
    float alpha;       // GGX alpha = roughness^2
    uint sourceSize;   // face size of radiance mip 0
    float sourceMips;  // radiance mip count
    uint firstRow;     // a slice of the mip (CubeFilter::recordPrefilterSlice): rows and faces
    uint firstFace;    // from these on
} pc;

// Every texel uses the same sample set in its own tangent frame, so the workgroup computes each
// batch once: tangent-space L in xyz and the source lod in w (w < 0: below the horizon).
shared vec4 batch[GROUP];

vec4 prefilterSample(uint i) {
    vec3 h = importanceSampleGGX(hammersley(i, pc.samples), pc.alpha);
    // With N = V: NdotH = VdotH = h.z, and L = 2 (V.H) H - V in tangent space.
    vec3 l = 2.0 * h.z * h - vec3(0.0, 0.0, 1.0);
    if (l.z <= 0.0) return vec4(0.0, 0.0, 0.0, -1.0);
    // pdf(L) = D * NdotH / (4 VdotH) = D / 4 for N = V. The lod makes one source texel cover the
    // sample's share of the lobe (Karis 2013, with the usual +1 bias against undersampling).
    float pdf = D_GGX(h.z, pc.alpha) * 0.25;
    float sampleSolidAngle = 1.0 / (float(pc.samples) * pdf + 1e-6);
    float texelSolidAngle = 4.0 * PI / (6.0 * float(pc.sourceSize * pc.sourceSize));
    float lod = 0.5 * log2(sampleSolidAngle / texelSolidAngle) + 1.0;
    return vec4(l, clamp(lod, 0.0, pc.sourceMips - 1.0));
}

void main() {
    uvec3 texel = gl_GlobalInvocationID + uvec3(0u, pc.firstRow, pc.firstFace);
    bool inside = texel.x < pc.size && texel.y < pc.size;  // no early return: barriers follow
    uvec3 clamped = min(texel, uvec3(pc.size - 1u, pc.size - 1u, 5u));
    mat3 frame = tangentFrame(cubeTexelDirection(clamped, pc.size));

    vec4 sum = vec4(0.0);  // rgba: a probe's premultiplied radiance and its coverage filter alike
    float weight = 0.0;
    for (uint base = 0u; base < pc.samples; base += GROUP) {
        uint count = min(GROUP, pc.samples - base);
        uint local = gl_LocalInvocationIndex;
        if (local < count) batch[local] = prefilterSample(base + local);
        barrier();
        for (uint i = 0u; i < count; ++i) {
            vec4 s = batch[i];
            if (s.w < 0.0) continue;
            sum += textureLod(radiance, frame * s.xyz, s.w) * s.z;  // weighted by NdotL
            weight += s.z;
        }
        barrier();
    }
    if (inside) imageStore(target, ivec3(texel), sum / max(weight, 1e-6));
}
