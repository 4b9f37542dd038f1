// Shared by the ibl_*.comp shaders: cube face texel directions (Vulkan cube face selection) and
// GGX sampling. D and V come from brdf.glsl so that the prefilter and the DFG table integrate
// exactly the lobe the lighting pass evaluates.
#ifndef IBL_COMMON_GLSL
#define IBL_COMMON_GLSL

#include "brdf.glsl"

// Direction through (s, t) in [0, 1]^2 of cube face `face` (+X, -X, +Y, -Y, +Z, -Z), inverting
// the Vulkan spec's face selection table (t grows downwards, row 0 at t = 0).
vec3 cubeDirection(uint face, vec2 st) {
    float sc = 2.0 * st.x - 1.0;
    float tc = 2.0 * st.y - 1.0;
    vec3 d;
    switch (face) {
    case 0u: d = vec3(1.0, -tc, -sc); break;
    case 1u: d = vec3(-1.0, -tc, sc); break;
    case 2u: d = vec3(sc, 1.0, tc); break;
    case 3u: d = vec3(sc, -1.0, -tc); break;
    case 4u: d = vec3(sc, -tc, 1.0); break;
    default: d = vec3(-sc, -tc, -1.0); break;
    }
    return normalize(d);
}

// Centre of texel `texel` on a face of `size` x `size` texels.
vec3 cubeTexelDirection(uvec3 texel, uint size) {
    return cubeDirection(texel.z, (vec2(texel.xy) + 0.5) / float(size));
}

vec2 hammersley(uint i, uint n) {
    return vec2((float(i) + 0.5) / float(n), float(bitfieldReverse(i)) * 2.3283064365386963e-10);
}

// Half vector in tangent space (z = normal) with pdf D(h) * NdotH.
vec3 importanceSampleGGX(vec2 xi, float alpha) {
    float phi = 2.0 * PI * xi.x;
    float cosTheta = sqrt((1.0 - xi.y) / (1.0 + (alpha * alpha - 1.0) * xi.y));
    float sinTheta = sqrt(max(1.0 - cosTheta * cosTheta, 0.0));
    return vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
}

// Orthonormal basis around n (Frisvad / Duff et al. 2017).
mat3 tangentFrame(vec3 n) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float b = n.x * n.y * a;
    vec3 t = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    vec3 bt = vec3(b, s + n.y * n.y * a, -n.y);
    return mat3(t, bt, n);
}

#endif
