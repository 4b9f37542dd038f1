#version 460
#extension GL_GOOGLE_include_directive : require
// render.shadow_mask: the sun's filtered visibility per pixel, from the depth prepass and the
// shadow map, so that the 16 MiB map dies before the G-buffer exists and lighting reads one
// byte instead of filtering.
//
// Filter: one textureGather with a comparison sampler returns the four depth tests around the
// lookup, weighted bilinearly here: a 2x2 PCF that is smooth across texels. lavapipe cannot
// linearly filter D32 (so no hardware PCF), and one gather costs about as much as one fetch,
// where the former 3x3 nearest filter cost nine.
#include "common/camera.glsl"
#include "engine/lighting_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depthTex;         // D32 reversed-Z, texelFetch only
layout(set = 0, binding = 1) uniform sampler2DShadow shadowMap;  // D32, compare GREATER_OR_EQUAL
// A uniform buffer, not storage: CPU drivers load uniform data once per SIMD group.
layout(set = 0, binding = 2, std140) uniform SceneLightingBuffer {
    SceneLighting scene;
};
layout(set = 0, binding = 3) uniform writeonly image2D outMask;  // R8_UNORM

layout(push_constant) uniform MaskConstants {
    mat4 invViewProj;
    vec4 cameraPosition;  // xyz
    uvec4 size;           // xy output size
} pc;

vec3 worldAt(ivec2 pixel, float depth) {
    return worldFromDepth(pixelCenterUV(pixel, ivec2(pc.size.xy)), depth, pc.invViewProj);
}

// Depth of a neighbour, or 0 (no surface) outside the image.
float depthAt(ivec2 pixel) {
    if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(uvec2(pixel), pc.size.xy)))
        return 0.0;
    return texelFetch(depthTex, pixel, 0).r;
}

// One tangent of the visible surface along an image axis: towards the neighbour whose depth
// is closer to the centre's, so that silhouettes do not bend the normal towards the background.
bool tangentAlong(ivec2 pixel, ivec2 axis, float depth, vec3 position, out vec3 tangent) {
    float dn = depthAt(pixel - axis);
    float dp = depthAt(pixel + axis);
    float en = dn > 0.0 ? abs(dn - depth) : 1e30;
    float ep = dp > 0.0 ? abs(dp - depth) : 1e30;
    if (min(en, ep) >= 1e30) return false;
    tangent = ep <= en ? worldAt(pixel + axis, dp) - position : position - worldAt(pixel - axis, dn);
    return true;
}

// Geometric normal of the depth buffer's surface, facing the camera. Falls back to the view
// direction for single-pixel features, which makes the normal offset a plain view offset.
vec3 geometricNormal(ivec2 pixel, float depth, vec3 position) {
    vec3 toEye = pc.cameraPosition.xyz - position;
    vec3 tx, ty;
    vec3 n = toEye;
    if (tangentAlong(pixel, ivec2(1, 0), depth, position, tx) &&
        tangentAlong(pixel, ivec2(0, 1), depth, position, ty))
        n = cross(tx, ty);
    float len2 = dot(n, n);
    if (!(len2 > 1e-30)) n = toEye, len2 = dot(n, n);
    n *= inversesqrt(len2);
    return dot(n, toEye) < 0.0 ? -n : n;
}

float sunVisibility(vec3 position, vec3 n) {
    float NoL = dot(n, scene.shadowToLight.xyz);
    // Normal offset grows with the light's slope over the surface, where acne starts.
    float sinTheta = sqrt(max(1.0 - NoL * NoL, 0.0));
    vec3 p = position + n * (scene.shadowParams.z * (1.0 + 2.0 * sinTheta));
    vec4 clip = scene.shadowViewProj * vec4(p, 1.0);
    vec2 uv = ndcToUV(clip.xy / clip.w);
    float depth = clip.z / clip.w;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || depth > 1.0) return 1.0;
    float size = scene.shadowParams.x;
    vec2 t = uv * size - 0.5;
    vec2 f = fract(t);
    // The corner the four nearest texel centres share: the gather returns exactly them.
    vec2 corner = (floor(t) + 1.0) / size;
    // Reversed-Z: lit where depth + bias >= the stored (nearest-to-light) depth.
    vec4 lit = textureGather(shadowMap, corner, depth + scene.shadowParams.y);
    // Gather order: x (i0, j1), y (i1, j1), z (i1, j0), w (i0, j0).
    return mix(mix(lit.w, lit.z, f.x), mix(lit.x, lit.y, f.x), f.y);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size.xy))) return;
    float depth = texelFetch(depthTex, pixel, 0).r;
    float visibility = 1.0;
    if (depth > 0.0) {
        vec3 position = worldAt(pixel, depth);
        visibility = sunVisibility(position, geometricNormal(pixel, depth, position));
    }
    imageStore(outMask, pixel, vec4(visibility));
}
