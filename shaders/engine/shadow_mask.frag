#version 460
#extension GL_GOOGLE_include_directive : require
// render.shadow_mask: the sun's filtered visibility per pixel (a fullscreen fragment pass into an
// R8 colour attachment, cheaper on lavapipe than compute imageStore), from the depth prepass and the
// shadow map, so that the 16 MiB map dies before the G-buffer exists and lighting reads one
// byte instead of filtering.
//
// Filter: one textureGather with a comparison sampler returns the four depth tests around the
// lookup, weighted bilinearly here: a 2x2 PCF that is smooth across texels. lavapipe cannot
// linearly filter D32 (so no hardware PCF), and one gather costs about as much as one fetch,
// where the former 3x3 nearest filter cost nine.
#include "common/camera.glsl"
#include "engine/lighting_common.glsl"

layout(set = 0, binding = 0) uniform sampler2D depthTex;         // D32 reversed-Z, gathered
layout(set = 0, binding = 1) uniform sampler2DShadow shadowMap;  // D32, compare GREATER_OR_EQUAL
// A uniform buffer, not storage: CPU drivers load uniform data once per SIMD group.
layout(set = 0, binding = 2, std140) uniform SceneShadowBuffer {
    SceneShadow scene;
};
layout(location = 0) out vec4 outMask;  // R8_UNORM

layout(push_constant) uniform MaskConstants {
    mat4 invViewProj;
    vec4 cameraPosition;  // xyz
    uvec4 size;           // xy output size
} pc;

vec3 worldAt(ivec2 pixel, float depth) {
    return worldFromDepth(pixelCenterUV(pixel, ivec2(pc.size.xy)), depth, pc.invViewProj);
}

// The pixel's depth and its four neighbours' (0, no surface, outside the image) from two
// gathers at the pixel's corners instead of five fetches.
struct Neighbourhood {
    float centre, left, right, up, down;
};
Neighbourhood depthsAround(ivec2 pixel) {
    vec2 size = vec2(pc.size.xy);
    // Gather order: x (i0, j1), y (i1, j1), z (i1, j0), w (i0, j0).
    vec4 tl = textureGather(depthTex, vec2(pixel) / size, 0);
    vec4 br = textureGather(depthTex, (vec2(pixel) + 1.0) / size, 0);
    Neighbourhood d;
    d.centre = tl.y;
    d.left = pixel.x > 0 ? tl.x : 0.0;
    d.up = pixel.y > 0 ? tl.z : 0.0;
    d.right = pixel.x + 1 < int(pc.size.x) ? br.z : 0.0;
    d.down = pixel.y + 1 < int(pc.size.y) ? br.x : 0.0;
    return d;
}

// One tangent of the visible surface along an image axis: towards the neighbour whose depth
// is closer to the centre's, so that silhouettes do not bend the normal towards the background.
// The side is chosen before the one unprojection (lavapipe would compute both sides of a
// branch or select).
bool tangentAlong(ivec2 pixel, ivec2 axis, float dn, float depth, float dp, vec3 position,
                  out vec3 tangent) {
    float en = dn > 0.0 ? abs(dn - depth) : 1e30;
    float ep = dp > 0.0 ? abs(dp - depth) : 1e30;
    float side = ep <= en ? 1.0 : -1.0;
    tangent = (worldAt(pixel + axis * int(side), side > 0.0 ? dp : dn) - position) * side;
    return min(en, ep) < 1e30;
}

// Geometric normal of the depth buffer's surface, facing the camera. Falls back to the view
// direction for single-pixel features, which makes the normal offset a plain view offset.
vec3 geometricNormal(ivec2 pixel, Neighbourhood d, vec3 position) {
    vec3 toEye = pc.cameraPosition.xyz - position;
    vec3 tx, ty;
    bool ok = tangentAlong(pixel, ivec2(1, 0), d.left, d.centre, d.right, position, tx);
    ok = tangentAlong(pixel, ivec2(0, 1), d.up, d.centre, d.down, position, ty) && ok;
    vec3 n = ok ? cross(tx, ty) : toEye;
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
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    Neighbourhood d = depthsAround(pixel);
    float visibility = 1.0;
    if (d.centre > 0.0) {
        vec3 position = worldAt(pixel, d.centre);
        visibility = sunVisibility(position, geometricNormal(pixel, d, position));
    }
    outMask = vec4(visibility);
}
